"""One repository address (``[project.urls] Repository``): README.md and CITATION.cff follow it.

tools/repository.py makes every link from the one setting; here the committed files must agree with
the setting as it is, and the links it makes for an address are checked for GitHub and another host.
"""

import pathlib
import re
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tools"))
import repository  # noqa: E402


def test_readme_and_citation_follow_the_setting():
    url = repository.repository_url(environ={})
    assert repository.disagreements(url) == []
    citation = (ROOT / "CITATION.cff").read_text(encoding="utf-8")
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    if url is None:  # no address: no link to one, and nothing standing in for it
        assert "repository-code" not in citation
        assert not re.search(r"https://(?:github|gitlab)\.com/|mybinder\.org/v2|OWNER/", readme + citation)
    else:
        assert f'repository-code: "{url}"' in citation and url in readme


def test_the_links_made_from_a_github_address():
    made = repository.links("https://github.com/example-org/mechanism-kinematics.git")
    assert made.repository == "https://github.com/example-org/mechanism-kinematics"
    assert made.issues == f"{made.repository}/issues"
    assert made.binder == ("https://mybinder.org/v2/gh/example-org/mechanism-kinematics/main"
                           "?urlpath=lab%2Ftree%2Fnotebooks%2F00_start_here.ipynb")
    assert made.colab_notebook("notebooks/03_fourbar_position.ipynb") == (
        "https://colab.research.google.com/github/example-org/mechanism-kinematics/blob/main/"
        "notebooks/03_fourbar_position.ipynb")
    block = repository.readme_block(made.repository)
    assert made.binder in block and made.issues in block


def test_other_hosts_get_binder_by_git_and_no_colab():
    made = repository.links("https://codeberg.org/example-org/mechanism-kinematics")
    assert made.binder.startswith("https://mybinder.org/v2/git/https%3A%2F%2Fcodeberg.org%2F")
    assert made.colab is None and made.colab_notebook("x.ipynb") is None


def test_the_environment_overrides_the_setting_and_bad_addresses_are_refused():
    assert repository.repository_url({repository.ENV: ""}) is None
    assert repository.repository_url({repository.ENV: "https://github.com/a/b/"}) == "https://github.com/a/b"
    for bad in ("http://github.com/a/b", "github.com/a/b", "https://github.com/a/b?x=1"):
        with pytest.raises(repository.RepositoryError):
            repository.repository_url({repository.ENV: bad})
    with pytest.raises(repository.RepositoryError):
        repository.links("https://github.com/only-owner")


def test_writing_an_address_into_the_readme_and_citation_and_back(tmp_path):
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    citation = (ROOT / "CITATION.cff").read_text(encoding="utf-8")
    url = "https://github.com/example-org/mechanism-kinematics"
    written = repository.expected_citation(citation, url)
    assert f'repository-code: "{url}"\nlicense:' in written
    assert repository.expected_citation(written, None) == repository.expected_citation(citation, None)
    with_links = repository.expected_readme(readme, url)
    assert "mybinder.org/v2/gh/example-org/mechanism-kinematics" in with_links
    assert repository.expected_readme(with_links, None) == repository.expected_readme(readme, None)


def test_the_links_follow_the_branch_setting():
    url = "https://github.com/example-org/mechanism-kinematics"
    made = repository.links(url, "release/2027")
    for link in (made.binder, made.source, made.notebook_source("notebooks/x.ipynb"),
                 made.colab_notebook("notebooks/x.ipynb")):
        assert "/release/2027" in link and "/main" not in link, link
    assert repository.links(url).branch == repository.repository_branch() == "main"  # the committed setting
    assert repository.repository_branch({repository.BRANCH_ENV: "dev"}) == "dev"


@pytest.mark.parametrize("branch", ["", "-x", "a..b", "a b", "x.lock", "a/x.lock/b", "../etc", "a/.b", "/a",
                                    "a/", "a\nb", 'main"><script>alert(1)</script>', "a?b", "a#b", None, 3])
def test_a_bad_branch_is_refused_by_name(branch):
    with pytest.raises(repository.RepositoryError, match=r"the repository's branch .*got"):
        repository.checked_branch(branch)
    if branch is not None:  # links(url, None): the branch setting
        with pytest.raises(repository.RepositoryError, match="branch"):
            repository.links("https://github.com/a/b", branch)
    if isinstance(branch, str) and "\n" not in branch:
        with pytest.raises(repository.RepositoryError, match=repository.BRANCH_ENV):
            repository.repository_branch({repository.BRANCH_ENV: branch})
