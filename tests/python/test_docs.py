"""The product's documents hold together: every "method.md §n" cited anywhere names a section of
docs/method.md, and every document path or relative link in README.md and docs/*.md exists.

Fast (text only, no simulation). The checkers are plain functions so that the tests below can
also show that they report a bad citation or a missing file.
"""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
METHOD = ROOT / "docs" / "method.md"

#: Files whose citations are checked (text files of the product, tests and docs).
TEXT_SUFFIXES = {".py", ".pyi", ".hpp", ".cpp", ".h", ".yaml", ".yml", ".md", ".xml", ".toml",
                 ".txt", ".cfg", ".sh", ".cmake"}
#: Folders never scanned when the file list does not come from git (build outputs, caches).
SKIP_DIRS = {".git", ".venv", "build", "dist", "out", "__pycache__", ".pytest_cache", "node_modules"}

#: A section number: "3", "2.6", "1.10".
_NUM = r"\d+(?:\.\d+)?"
#: "method.md §2.6", "method.md §1.2–1.5", "method.md §2.1-2.4", "method.md §0/1.1".
CITATION = re.compile(rf"method\.md`*\s*§\s*({_NUM})(?:\s*[–\-/]\s*({_NUM}))?")
#: Inside docs/method.md itself: a bare "§2.6", "§1.7–§1.9", "§2.6/2.7".
BARE = re.compile(rf"§\s*({_NUM})(?:\s*[–\-/]\s*§?\s*({_NUM}))?")
#: "## 3. Grasp pose", "### 2.6 Guards", "### 1.10 Workspace limits (extension)".
HEADING = re.compile(rf"^#{{2,4}}\s+({_NUM})\.?\s+\S", re.MULTILINE)
#: "docs/method.md", "docs/rerun_recording.png" mentioned in a document's text.
DOC_PATH = re.compile(r"(?<![\w/.-])docs/[\w./-]*[\w]")
#: Markdown links and images: [text](target) / ![alt](target).
LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")


def section_numbers(method_text: str) -> set[str]:
    """The section numbers of the headings of ``method_text``."""
    return set(HEADING.findall(method_text))


def cited_sections(text: str, pattern: re.Pattern = CITATION) -> list[tuple[int, str]]:
    """(line number, section) of every section cited in ``text``; both ends of a range."""
    out = []
    for m in pattern.finditer(text):
        line = text.count("\n", 0, m.start()) + 1
        out += [(line, s) for s in m.groups() if s]
    return out


def bad_citations(files: dict[str, str], sections: set[str]) -> list[str]:
    """"path:line: §n" for every cited section that is no heading of docs/method.md.
    ``files``: path -> text; docs/method.md's own bare "§n" references are checked too."""
    bad = []
    for path, text in files.items():
        found = cited_sections(text)
        if path == "docs/method.md":
            found += cited_sections(text, BARE)
        bad += [f"{path}:{line}: §{s}" for line, s in found if s not in sections]
    return sorted(set(bad))


def missing_paths(doc: str, text: str, root: Path) -> list[str]:
    """"doc: target" for every docs/<file> mentioned and every relative link in ``text`` (a
    document at ``root / doc``) that does not exist."""
    missing = []
    for p in DOC_PATH.findall(text):
        if not (root / p).exists():
            missing.append(f"{doc}: {p}")
    for target in LINK.findall(text):
        if re.match(r"^[a-z][a-z0-9+.-]*:", target) or target.startswith("#"):
            continue  # a URL (http:, mailto:) or an anchor in the same document
        path = target.split("#", 1)[0]
        if path and not ((root / doc).parent / path).exists():
            missing.append(f"{doc}: {target}")
    return list(dict.fromkeys(missing))


def tracked_text_files(root: Path) -> list[str]:
    """Repository-relative paths of the text files to scan: git's tracked files when this is a
    git checkout, else every file outside build outputs and caches."""
    try:
        out = subprocess.run(["git", "ls-files", "-z"], cwd=root, capture_output=True, check=True,
                             timeout=30).stdout.decode("utf-8", "replace")
        paths = [p for p in out.split("\0") if p]
    except (OSError, subprocess.SubprocessError):
        paths = [str(p.relative_to(root)) for p in root.rglob("*")
                 if p.is_file() and not SKIP_DIRS.intersection(p.relative_to(root).parts)]
    return sorted(p for p in paths if Path(p).suffix in TEXT_SUFFIXES and (root / p).is_file())


def read_texts(root: Path, paths) -> dict[str, str]:
    return {p: (root / p).read_text(encoding="utf-8", errors="replace") for p in paths}


@pytest.fixture(scope="module")
def sections() -> set[str]:
    assert METHOD.is_file(), "docs/method.md is missing"
    return section_numbers(METHOD.read_text(encoding="utf-8"))


def test_method_md_has_the_methods_sections_in_order(sections):
    for n in ["0", "1", "2", "3", "4", "5", "6", "7", "8"] + [f"1.{k}" for k in range(1, 7)] \
            + [f"2.{k}" for k in range(1, 8)]:
        assert n in sections, f"docs/method.md has no section {n}"


def test_every_cited_section_exists_in_method_md(sections):
    files = read_texts(ROOT, tracked_text_files(ROOT))
    files["docs/method.md"] = METHOD.read_text(encoding="utf-8")  # also before it is committed
    n_citations = sum(len(cited_sections(t)) for t in files.values())
    assert n_citations > 100, f"only {n_citations} citations of method.md found: is the scan broken?"
    bad = bad_citations(files, sections)
    assert not bad, "citations of sections docs/method.md does not have:\n" + "\n".join(bad)


def test_documents_name_only_files_that_exist():
    docs = ["README.md"] + sorted(str(p.relative_to(ROOT)) for p in (ROOT / "docs").glob("*.md"))
    missing = [m for d in docs for m in missing_paths(d, (ROOT / d).read_text(encoding="utf-8"), ROOT)]
    assert not missing, "documents name files that do not exist:\n" + "\n".join(missing)


# ---- the checkers can fail -------------------------------------------------------------------

def test_a_citation_of_a_missing_section_is_reported():
    sections = section_numbers("## 1. Scene\n### 1.2 Planes\n### 1.5 Lock\n## 2. Estimate\n")
    assert sections == {"1", "1.2", "1.5", "2"}
    files = {"a.py": "# method.md §1.2–1.5 ok\n# method.md §2.6 missing\n",
             "b.hpp": "// docs/method.md §1.2-1.9: the range's far end is missing\n",
             "docs/method.md": "see §1.5 and §7\n"}
    assert bad_citations(files, sections) == ["a.py:2: §2.6", "b.hpp:1: §1.9", "docs/method.md:1: §7"]


def test_a_missing_document_or_link_is_reported(tmp_path):
    (tmp_path / "docs").mkdir()
    (tmp_path / "docs" / "method.md").write_text("x")
    text = ("See docs/method.md and docs/gone.md; [method](docs/method.md#1-scene), "
            "[web](https://example.org/x), [here](#top), ![pic](docs/missing.png).")
    assert missing_paths("README.md", text, tmp_path) == [
        "README.md: docs/gone.md", "README.md: docs/missing.png"]
