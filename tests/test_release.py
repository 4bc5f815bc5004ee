"""The release's papers: the version in one place each, the licences' official texts, a complete
citation, a changelog entry, and a CONTRIBUTING.md whose every named file and command exists."""

import hashlib
import pathlib
import re
import tomllib

import yaml

ROOT = pathlib.Path(__file__).resolve().parent.parent
PROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]
CITATION = yaml.safe_load((ROOT / "CITATION.cff").read_text(encoding="utf-8"))
# SHA-256 of the BSD-3-Clause text as SPDX and the OSI publish it (everything after the copyright line),
# its words joined by single spaces
BSD_3_CLAUSE_WORDS = "70435d703f5e4bdca9a1fa6b9291501b0dd850d2ad5457b491ce936217b1e063"
# SHA-256 of Creative Commons' plain-text legal code of CC BY 4.0 (legalcode.txt), byte for byte
CC_BY_4_LEGALCODE = "2a82ac9bbc3e3ee066908381e8d373896db5a6025d083fbd59692fe9ccfb9111"


def test_license_is_the_bsd_3_clause_text():
    copyright_line, blank, body = (ROOT / "LICENSE").read_text(encoding="utf-8").split("\n", 2)
    assert re.fullmatch(r"Copyright \(c\) 20\d\d, .+\.", copyright_line) and blank == ""
    assert hashlib.sha256(" ".join(body.split()).encode()).hexdigest() == BSD_3_CLAUSE_WORDS


def test_license_content_is_the_cc_by_4_legal_code_verbatim():
    text = (ROOT / "LICENSE-content").read_bytes()
    assert hashlib.sha256(text).hexdigest() == CC_BY_4_LEGALCODE
    assert text.startswith(b"Attribution 4.0 International\n")


def test_citation_is_complete_and_matches_the_project():
    for key in ("cff-version", "message", "title", "authors", "version", "date-released", "license",
                "abstract", "keywords", "type"):
        assert CITATION.get(key), f"CITATION.cff has no {key}"
    assert CITATION["cff-version"] == "1.2.0" and CITATION["type"] == "software"
    assert str(CITATION["version"]) == PROJECT["version"]
    assert re.fullmatch(r"\d{4}-\d\d-\d\d", str(CITATION["date-released"]))
    assert CITATION["license"] == ["BSD-3-Clause", "CC-BY-4.0"]
    assert all(author.get("name") or author.get("family-names") for author in CITATION["authors"])
    for author in CITATION["authors"]:  # a person, or an entity with a name of its own: no placeholder
        name = author.get("name", "")
        assert not re.match(r"(?i)(the )?(authors?|todo|tbd|name|placeholder)\b", name), author


def test_the_changelog_opens_with_this_version():
    changelog = (ROOT / "CHANGELOG.md").read_text(encoding="utf-8")
    first = re.search(r"^## (\S+) — (\d{4}-\d\d-\d\d)$", changelog, re.M)
    assert first and first.group(1) == PROJECT["version"]
    assert first.group(2) == str(CITATION["date-released"])


def test_the_python_versions_claimed_are_the_ones_tested():
    classifiers = {c.rsplit(" ", 1)[1] for c in PROJECT["classifiers"] if c.startswith("Programming")}
    assert classifiers == {"3.11", "3.12", "3.13"} and PROJECT["requires-python"] == ">=3.11"
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    assert "Needs Python 3.11, 3.12 or 3.13 (each tested: `make test-pythons`)" in readme
    makefile = (ROOT / "Makefile").read_text(encoding="utf-8")
    assert re.search(r"^PYTHONS \?= 3\.11 3\.12 3\.13$", makefile, re.M)


def test_every_file_and_make_target_contributing_names_exists():
    text = (ROOT / "CONTRIBUTING.md").read_text(encoding="utf-8")
    makefile = (ROOT / "Makefile").read_text(encoding="utf-8")
    targets = set(re.findall(r"^([a-z][\w-]*):", makefile, re.M))
    for target in re.findall(r"`make ([a-z][\w-]*)", text):
        assert target in targets, f"CONTRIBUTING.md names `make {target}`, which the Makefile lacks"
    for path in re.findall(r"`((?:tests|tools|course_lib|notebooks|binder)/[\w./-]+)`", text):
        if "<" in path or "NN" in path or path.endswith("/"):
            assert (ROOT / path.split("<")[0].split("NN")[0]).parent.exists(), path
            continue
        assert (ROOT / path).exists(), f"CONTRIBUTING.md names {path}, which does not exist"
    for name in re.findall(r"`([\w-]+\.(?:txt|toml|cff|md))`", text):
        assert (ROOT / name).exists(), f"CONTRIBUTING.md names {name}, which does not exist"


def test_the_package_reports_the_released_version():
    import course_lib

    assert course_lib.__version__ == PROJECT["version"]
