"""The release and the site refuse a bad setting, say which and why, and write nothing.

tools/make_dist.py runs on a small git repository made for each test (its own copy of the tool, the
files a bundle needs, one commit), so any version, ref or output can be tried without touching this
checkout.  tools/repository.py runs on a temporary copy too (its own README.md, CITATION.cff and
pyproject.toml beside it), with the address given by the environment or by pyproject.toml.  The site's
pieces that write the addresses (tools/build_site.py: landing page and _config.yml) are called directly.
"""

import datetime
import json
import os
import pathlib
import shutil
import subprocess
import sys
import zipfile

import pytest
import yaml

ROOT = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tools"))
import build_site  # noqa: E402
import make_dist  # noqa: E402
import repository  # noqa: E402

GIT = ["git", "-c", "user.name=Test", "-c", "user.email=test@example.invalid", "-c", "commit.gpgsign=false",
       "-c", "init.defaultBranch=main"]
CITATION = (ROOT / "CITATION.cff").read_text(encoding="utf-8")


# ---------------------------------------------------------------- make_dist on a repository of its own


def _pyproject(version_line: str) -> str:
    return f'[project]\nname = "course_lib"\n{version_line}\n'


def _files(version_line: str = 'version = "1.0.0"', library: str = "1.0.0") -> dict[str, str]:
    return {
        "pyproject.toml": _pyproject(version_line),
        "course_lib/__init__.py": f'"""course_lib."""\n\n__version__ = {library!r}\n',
        "environment.txt": "numpy\n", "environment.lock": "numpy==2.4.6\n", "LICENSE": "BSD\n",
        "LICENSE-content": "CC-BY\n",
        "CITATION.cff": CITATION, "notebooks/00_start_here.ipynb": "{}\n",
    }


def _repo(where: pathlib.Path, files: dict[str, str]) -> pathlib.Path:
    repo = where / "repo"
    (repo / "tools").mkdir(parents=True)
    shutil.copy2(ROOT / "tools" / "make_dist.py", repo / "tools" / "make_dist.py")
    for path, text in files.items():
        (repo / path).parent.mkdir(parents=True, exist_ok=True)
        (repo / path).write_text(text, encoding="utf-8")
    subprocess.run([*GIT, "init", "-q"], cwd=repo, check=True)
    subprocess.run([*GIT, "add", "-A"], cwd=repo, check=True)
    subprocess.run([*GIT, "commit", "-q", "-m", "release"], cwd=repo, check=True)
    return repo


def _everything(where: pathlib.Path) -> dict[str, bytes]:
    """Every file under ``where`` (the test repository's .git left out) and its content."""
    return {path.relative_to(where).as_posix(): path.read_bytes() for path in sorted(where.rglob("*"))
            if path.is_file() and ".git" not in path.relative_to(where).parts}


def _make_dist(repo: pathlib.Path, *arguments: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, str(repo / "tools" / "make_dist.py"), *arguments], cwd=repo,
                          capture_output=True, text=True, timeout=120)


def _refused(result: subprocess.CompletedProcess, *words: str) -> None:
    assert result.returncode == 2, result.stdout + result.stderr
    assert "Traceback" not in result.stderr, result.stderr
    assert result.stderr.startswith("make_dist: ") and result.stderr.count("\n") == 1, result.stderr
    assert "nothing was written" in result.stderr
    for word in words:
        assert word in result.stderr, (word, result.stderr)


def test_a_sound_copy_is_released_inside_its_output_folder(tmp_path):
    repo = _repo(tmp_path, _files())
    assert not (tmp_path / "a").exists()
    out = tmp_path / "a" / "b" / "out"
    result = _make_dist(repo, "--output", str(out))
    assert result.returncode == 0, result.stderr
    top = "mechanism-kinematics-1.0.0"
    assert sorted(path.name for path in out.iterdir()) == [".gitignore", f"{top}-instructor.zip",
                                                           f"{top}-student.zip"]
    with zipfile.ZipFile(out / f"{top}-student.zip") as archive:
        names = archive.namelist()
    assert "mechanism-kinematics-1.0.0/README.md" in names
    assert all(name.startswith(f"{top}/") and ".." not in name.split("/") for name in names)
    assert {path for path in _everything(tmp_path) if not path.startswith("repo/")} == {
        f"a/b/out/{name}" for name in (".gitignore", f"{top}-instructor.zip", f"{top}-student.zip")}


@pytest.mark.parametrize("version", ["../../../escaped", "", "1.0/2", "1.0 beta <b>", "v1.0.0", "1.0-beta",
                                     "1.0.0+local", " 1.0.0", "1.0.0\n", "01.0"])
def test_a_version_that_is_no_pep_440_release_is_refused_and_nothing_is_written(tmp_path, version):
    # course_lib says the same, so only the version's form can be at fault
    repo = _repo(tmp_path / "a" / "b" / "c", _files(f"version = {json.dumps(version)}", library=version))
    before = _everything(tmp_path)
    out = tmp_path / "a" / "b" / "c" / "out"
    _refused(_make_dist(repo, "--output", str(out)), "[project] version", "PEP 440", repr(version))
    assert _everything(tmp_path) == before and not out.exists()
    assert not (tmp_path / "escaped-student.zip").exists()
    assert not list(tmp_path.rglob("*.zip"))


def test_a_version_course_lib_does_not_report_is_refused(tmp_path):
    repo = _repo(tmp_path, _files('version = "2.0.0"', library="1.0.0"))
    before = _everything(tmp_path)
    _refused(_make_dist(repo, "--output", str(tmp_path / "out")), "[project] version", "'2.0.0'",
             "course_lib.__version__", "'1.0.0'")
    assert _everything(tmp_path) == before


def test_a_course_lib_without_a_version_is_refused(tmp_path):
    files = _files()
    files["course_lib/__init__.py"] = '"""course_lib, its version forgotten."""\n'
    repo = _repo(tmp_path, files)
    before = _everything(tmp_path)
    _refused(_make_dist(repo, "--output", str(tmp_path / "out")), "course_lib/__init__.py", "__version__",
             "'1.0.0'")
    assert _everything(tmp_path) == before


@pytest.mark.parametrize("line", ["", "version = 1.0.0", "version = 1", 'version = "1.0.0'])
def test_a_missing_or_unquoted_version_line_gives_one_readable_message(tmp_path, line):
    repo = _repo(tmp_path, _files(line))
    before = _everything(tmp_path)
    _refused(_make_dist(repo, "--output", str(tmp_path / "out")), "pyproject.toml", "[project] version")
    assert _everything(tmp_path) == before


@pytest.mark.parametrize("ref", ["nosuchref", "--name-only", "-p", "--output=/tmp", "HEAD:pyproject.toml"])
def test_a_ref_that_is_no_commit_or_reads_as_an_option_is_refused(tmp_path, ref):
    repo = _repo(tmp_path, _files())
    before = _everything(tmp_path)
    _refused(_make_dist(repo, "--output", str(tmp_path / "out"), f"--ref={ref}"), "--ref", repr(ref))
    assert _everything(tmp_path) == before
    with pytest.raises(make_dist.ReleaseError, match="--ref"):
        make_dist.commit_of(ref)


def test_the_ref_may_name_a_commit_by_tag_or_hash(tmp_path):
    repo = _repo(tmp_path, _files())
    subprocess.run([*GIT, "tag", "v1.0.0"], cwd=repo, check=True)
    commit = subprocess.run(["git", "rev-parse", "HEAD"], cwd=repo, capture_output=True, text=True,
                            check=True).stdout.strip()
    for ref in ("v1.0.0", commit, commit[:10], "main"):
        result = _make_dist(repo, "--output", str(tmp_path / ref), f"--ref={ref}")
        assert result.returncode == 0, result.stderr
        assert (tmp_path / ref / "mechanism-kinematics-1.0.0-student.zip").is_file()


@pytest.mark.parametrize("inside", [False, True])
def test_an_output_that_is_an_existing_file_is_refused(tmp_path, inside):
    repo = _repo(tmp_path, _files())
    blocker = tmp_path / "dist"
    blocker.write_text("a file, not a folder\n")
    before = _everything(tmp_path)
    output = blocker / "sub" if inside else blocker
    _refused(_make_dist(repo, "--output", str(output)), "--output", str(blocker), "is a file")
    assert _everything(tmp_path) == before


@pytest.mark.parametrize("path", ["../evil.py", "a/../../evil.py", "/etc/evil", "a//b", "./a", "a/./b",
                                  "a\\..\\b", "C:/evil", "a/\nb", ""])
def test_an_archive_entry_outside_the_bundles_folder_is_refused_before_anything_is_written(tmp_path, path):
    target = tmp_path / "out" / "bundle.zip"
    with pytest.raises(make_dist.ReleaseError, match="inside the bundle's folder"):
        make_dist.write_zip(target, "mechanism-kinematics-1.0.0",
                            {"ok.txt": (b"ok", False), path: (b"", False)}, datetime.date(2026, 1, 1))
    assert not (tmp_path / "out").exists()
    for top in ("..", ".", "a/b", ""):
        with pytest.raises(make_dist.ReleaseError):
            make_dist.entry_name(top, "ok.txt")
    assert make_dist.entry_name("mechanism-kinematics-1.0.0", "notebooks/exercises/ex01.ipynb") == (
        "mechanism-kinematics-1.0.0/notebooks/exercises/ex01.ipynb")


GOOD_VERSIONS = ["1.0.0", "0.1", "2.1rc1", "1.0a2", "1.0.post2", "3.0.dev4", "1!2.0", "1.0.0b1.post1.dev2"]
BAD_VERSIONS = ["", "../x", "1.0/2", "1.0 beta <b>", "v1.0", "1.0-beta", "1.0.0+local", "1.01", "1.0.",
                ".1", "1..0", "1.0rc", "1.0.0\n", "1.0.0 ", "١.٠", None, 1.0]


@pytest.mark.parametrize("with_packaging", [True, False])
def test_a_release_version_is_a_pep_440_version_in_its_normal_form(monkeypatch, with_packaging):
    if not with_packaging:  # the regex alone, as where packaging is not installed
        monkeypatch.setattr(make_dist, "Version", None)
    else:
        assert make_dist.Version is not None, "packaging is importable in the development environment"
    assert all(make_dist.is_release_version(version) for version in GOOD_VERSIONS)
    assert not any(make_dist.is_release_version(version) for version in BAD_VERSIONS)


def test_this_checkouts_version_passes_its_own_checks():
    files = make_dist.committed()
    assert make_dist.project_version(files) == make_dist.library_version(files)


# ---------------------------------------------------------------- repository.py on a copy

BAD_ADDRESSES = [
    'https://github.com/a/b"><script>alert(1)</script>',
    "https://github.com/a/b)](javascript:alert(1))",
    "https://github.com/a/b'onmouseover='alert(1)",
    "https://github.com/a/b\ninjected: true",
    "https://github.com/a/b\r\nx",
    "https://github.com/a/b c",
    "https://github.com/a/b\x7f",
    "https://user:secret@github.com/a/b",
    "https://token@github.com/a/b",
    "https://github.com:99999/a/b",
    "https://github.com:0/a/b",
    "https://github.com:/a/b",
    "https://github.com/../a/b",
    "https://github.com/a/../../b",
    "https://github.com/a/./b",
    "https://github.com//a/b",
    "https://github.com/a/b?x=1",
    "https://github.com/a/b#top",
    "https://github.com/a/b%2e%2e",
    "https://-github.com/a/b",
    "https://github..com/a/b",
    "https://githüb.com/a/b",
    "http://github.com/a/b",
    "javascript:alert(1)//github.com/a/b",
    "github.com/a/b",
    "https:///a/b",
]
GOOD_ADDRESSES = {  # as given: as written
    "https://github.com/example-org/mechanism-kinematics": "https://github.com/example-org/mechanism-kinematics",
    "https://github.com/example-org/mechanism-kinematics.git/": "https://github.com/example-org/mechanism-kinematics",
    "https://gitlab.com/group/sub.group/name_1": "https://gitlab.com/group/sub.group/name_1",
    "https://git.example.edu:8443/a/b": "https://git.example.edu:8443/a/b",
    "  https://codeberg.org/o-o/n.n  ": "https://codeberg.org/o-o/n.n",
}
README_TEXT = ("# A course\n\nText.\n\n## Run it elsewhere\n\n" + repository.README_START + "\n"
               + repository.README_END + "\n\nMore text.\n")


def _pyproject_with(url: str | None = None, hub: str | None = None) -> str:
    text = '[project]\nname = "course_lib"\nversion = "1.0.0"\n\n[project.urls]\n'
    if url is not None:
        text += f"Repository = {json.dumps(url)}\n"  # a JSON string is a TOML basic string
    if hub is not None:
        text += f"\n[tool.course]\njupyterhub-url = {json.dumps(hub)}\n"
    return text


@pytest.fixture
def copy(tmp_path):
    """tools/repository.py beside its own README.md, CITATION.cff (this one's) and pyproject.toml."""
    (tmp_path / "tools").mkdir()
    shutil.copy2(ROOT / "tools" / "repository.py", tmp_path / "tools" / "repository.py")
    (tmp_path / "README.md").write_text(README_TEXT, encoding="utf-8")
    (tmp_path / "CITATION.cff").write_text(repository.expected_citation(CITATION, None), encoding="utf-8")
    (tmp_path / "pyproject.toml").write_text(_pyproject_with(), encoding="utf-8")
    return tmp_path


def _repository(copy: pathlib.Path, *arguments: str, url: str | None = None,
                hub: str | None = None) -> subprocess.CompletedProcess:
    env = {key: value for key, value in os.environ.items() if key not in (repository.ENV, repository.HUB_ENV)}
    if url is not None:
        env[repository.ENV] = url
    if hub is not None:
        env[repository.HUB_ENV] = hub
    return subprocess.run([sys.executable, str(copy / "tools" / "repository.py"), *arguments], cwd=copy,
                          env=env, capture_output=True, text=True, timeout=60)


def _files_of(copy: pathlib.Path) -> dict[str, bytes]:
    return {name: (copy / name).read_bytes() for name in ("README.md", "CITATION.cff", "pyproject.toml")}


def _shown(address: str) -> str:
    return repr(address.replace("user:secret@", "***@").replace("token@", "***@"))


@pytest.mark.parametrize("address", BAD_ADDRESSES)
def test_a_bad_repository_address_is_refused_by_write_and_check_and_nothing_is_written(copy, address):
    before = _files_of(copy)
    for command in ("--write", "--check", "--write --check"):
        result = _repository(copy, *command.split(), url=address)
        assert result.returncode == 2, (command, result.stdout, result.stderr)
        assert "Traceback" not in result.stderr and result.stderr.count("\n") == 1, result.stderr
        assert f"the repository's address ({repository.ENV})" in result.stderr
        assert _shown(address) in result.stderr
        assert "secret" not in result.stderr and "token" not in result.stderr
        assert _files_of(copy) == before
    with pytest.raises(repository.RepositoryError, match="the repository's address"):
        repository.repository_url({repository.ENV: address})
    with pytest.raises(repository.RepositoryError):
        repository.links(address)
    with pytest.raises(repository.RepositoryError):
        repository.expected_citation(CITATION, address)
    with pytest.raises(repository.RepositoryError):
        repository.readme_block(address)


@pytest.mark.parametrize("address", BAD_ADDRESSES[:4] + ["https://user:secret@github.com/a/b"])
def test_a_bad_address_in_pyproject_is_refused_with_the_settings_name(copy, address):
    (copy / "pyproject.toml").write_text(_pyproject_with(address), encoding="utf-8")
    before = _files_of(copy)
    result = _repository(copy, "--write")
    assert result.returncode == 2 and "Traceback" not in result.stderr, result.stderr
    assert "[project.urls] Repository in pyproject.toml" in result.stderr and _shown(address) in result.stderr
    assert _files_of(copy) == before


@pytest.mark.parametrize("hub", [h.replace("/a/b", "") for h in BAD_ADDRESSES[:12]] + ["https://hub.example.edu/.."])
@pytest.mark.parametrize("where", ["environment", "pyproject"])
def test_a_bad_jupyterhub_address_is_refused_and_nothing_is_written(copy, hub, where):
    good = "https://github.com/example-org/mechanism-kinematics"
    if where == "pyproject":
        (copy / "pyproject.toml").write_text(_pyproject_with(good, hub=hub), encoding="utf-8")
        before = _files_of(copy)
        result = _repository(copy, "--write")
        setting = "[tool.course] jupyterhub-url in pyproject.toml"
    else:
        before = _files_of(copy)
        result = _repository(copy, "--write", url=good, hub=hub)
        setting = repository.HUB_ENV
    assert result.returncode == 2 and "Traceback" not in result.stderr, result.stderr
    assert f"the JupyterHub's address ({setting})" in result.stderr
    assert _shown(hub) in result.stderr
    assert _files_of(copy) == before
    with pytest.raises(repository.RepositoryError, match="JupyterHub"):
        build_site.site_config(good, hub)


@pytest.mark.parametrize("address", sorted(GOOD_ADDRESSES))
@pytest.mark.parametrize("where", ["environment", "pyproject"])
def test_write_then_check_agree_and_the_citation_stays_valid_yaml(copy, address, where):
    written = GOOD_ADDRESSES[address]
    if where == "pyproject":
        (copy / "pyproject.toml").write_text(_pyproject_with(address), encoding="utf-8")
        url = None
    else:
        url = address
    result = _repository(copy, "--write", url=url)
    assert result.returncode == 0, result.stdout + result.stderr
    check = _repository(copy, "--check", url=url)
    assert check.returncode == 0, check.stdout + check.stderr
    citation = yaml.safe_load((copy / "CITATION.cff").read_text(encoding="utf-8"))
    assert citation["repository-code"] == written
    without = yaml.safe_load(repository.expected_citation(CITATION, None))
    assert {key: value for key, value in citation.items() if key != "repository-code"} == without
    readme = (copy / "README.md").read_text(encoding="utf-8")
    assert f"Repository: <{written}>" in readme and readme.endswith("\nMore text.\n")
    # and back to no address: the files as they were
    (copy / "pyproject.toml").write_text(_pyproject_with(), encoding="utf-8")
    assert _repository(copy, "--write", url="").returncode == 0
    assert _repository(copy, "--check", url="").returncode == 0
    assert (copy / "README.md").read_text(encoding="utf-8") == README_TEXT
    assert "repository-code" not in yaml.safe_load((copy / "CITATION.cff").read_text(encoding="utf-8"))


def test_check_reports_a_citation_that_is_not_valid_yaml(copy):
    url = "https://github.com/example-org/mechanism-kinematics"
    assert _repository(copy, "--write", url=url).returncode == 0
    citation = copy / "CITATION.cff"
    citation.write_text(citation.read_text(encoding="utf-8").replace('title: "', 'title: "broken\n  "x'),
                        encoding="utf-8")
    result = _repository(copy, "--check", url=url)
    assert result.returncode == 1 and "CITATION.cff is not valid YAML" in result.stdout, result.stdout
    before = _files_of(copy)
    refused = _repository(copy, "--write", url=url)  # --write would leave it invalid: it writes nothing
    assert refused.returncode == 2 and "not valid YAML" in refused.stderr and _files_of(copy) == before


def test_markdown_links_cannot_be_closed_by_the_address():
    hostile = "https://x.org/a)](javascript:alert(1)) <b> \"q\" 'q' [x]\n\\"
    escaped = repository.markdown_url(hostile)
    assert not any(c in escaped for c in "()<>[]\"' \n\\"), escaped
    url = "https://mybinder.org/v2/gh/a/b/main?urlpath=lab%2Ftree%2Fx.ipynb"
    assert repository.markdown_url(url) == url  # a checked address is written as it is


# ---------------------------------------------------------------- the site's landing page and _config.yml


def test_the_site_refuses_a_bad_address_and_escapes_the_links_it_writes():
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    for address in [*BAD_ADDRESSES, "https://github.com/a/b\x00"]:
        with pytest.raises(repository.RepositoryError):
            build_site.landing_page(readme, address)
        with pytest.raises(repository.RepositoryError):
            build_site.site_config(address)
    anchor = build_site._anchor('https://x.org/a" onmouseover="alert(1)', "<b>it's</b>")
    assert anchor == ('<a href="https://x.org/a&quot; onmouseover=&quot;alert(1)">'
                      "&lt;b&gt;it&#x27;s&lt;/b&gt;</a>")
    good = "https://github.com/example-org/mechanism-kinematics"
    page = build_site.landing_page(readme, good)
    assert f'<a href="{good}">the repository</a>' in page and f'<a href="{good}/issues">' in page
    config = yaml.safe_load(build_site.site_config(good, "https://hub.example.edu:8000/jupyter/"))
    assert config["repository"]["url"] == good
    assert config["launch_buttons"]["jupyterhub_url"] == "https://hub.example.edu:8000/jupyter"
