"""The documentation a newcomer navigates (issue 30, part 7): a short README that links the docs
pages, every relative link in README.md and docs/*.md resolving to a file (and a heading, for an
`#anchor`), and every input format named in the README."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from zedo_cli.formats import INPUT_FORMATS

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
PAGES = [
    README,
    *sorted((ROOT / "docs").glob("*.md")),
    ROOT / "benchmarks" / "README.md",
    ROOT / "experiments" / "README.md",
]
MAX_README_LINES = 300

# [text](target) and ![alt](target); a target has no spaces (an optional "title" is dropped).
_LINK = re.compile(r"!?\[[^\]]*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
_FENCE = re.compile(r"^\s*(```|~~~)")
_HEADING = re.compile(r"^(#{1,6})\s+(.*?)\s*#*\s*$")


def _prose(text: str) -> list[str]:
    """The lines outside fenced and indented code blocks, where links and headings count."""
    lines, fenced = [], False
    for line in text.splitlines():
        if _FENCE.match(line):
            fenced = not fenced
            continue
        if not fenced and not line.startswith("    "):
            lines.append(line)
    return lines


def github_slug(heading: str) -> str:
    """GitHub's anchor for a heading: lowercase, markup and punctuation dropped (hyphens and
    underscores kept), each space a hyphen."""
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", heading)  # a link keeps its text
    text = text.replace("`", "").lower()
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def anchors(path: Path) -> set[str]:
    """Every heading's anchor in a markdown file, with GitHub's -1, -2 suffixes for repeats."""
    seen: dict[str, int] = {}
    out = set()
    for line in _prose(path.read_text()):
        match = _HEADING.match(line)
        if not match:
            continue
        slug = github_slug(match.group(2))
        count = seen.get(slug, 0)
        seen[slug] = count + 1
        out.add(slug if count == 0 else f"{slug}-{count}")
    return out


def relative_links(path: Path) -> list[str]:
    targets = []
    for line in _prose(path.read_text()):
        line = re.sub(r"`[^`]*`", "", line)  # code spans hold no links
        targets += [t for t in _LINK.findall(line) if not re.match(r"^[a-z][a-z0-9+.-]*:", t)]
    return targets


def broken_links(path: Path) -> list[str]:
    """The relative links of a markdown file that name a missing file or a missing heading."""
    broken = []
    for target in relative_links(path):
        file_part, _, anchor = target.partition("#")
        dest = (path.parent / file_part).resolve() if file_part else path
        if not dest.exists():
            broken.append(f"{target} (no such file)")
        elif anchor and dest.suffix == ".md" and anchor not in anchors(dest):
            broken.append(f"{target} (no heading #{anchor} in {dest.name})")
    return broken


def test_the_readme_is_short() -> None:
    lines = len(README.read_text().splitlines())
    assert lines <= MAX_README_LINES, f"README.md has {lines} lines; move detail into docs/"


@pytest.mark.parametrize("page", PAGES, ids=lambda p: str(p.relative_to(ROOT)))
def test_every_relative_link_resolves(page: Path) -> None:
    assert broken_links(page) == []


def test_the_readme_links_the_docs_pages() -> None:
    linked = {
        (README.parent / t.partition("#")[0]).resolve()
        for t in relative_links(README)
        if t.startswith("docs/") and t.partition("#")[0].endswith(".md")
    }
    assert len(linked) >= 5, sorted(str(p) for p in linked)


def test_the_readme_names_every_input_format() -> None:
    readme = README.read_text()
    missing = [name for name in INPUT_FORMATS if name != "auto" and f"`{name}`" not in readme]
    assert missing == []


def test_the_link_checker_sees_broken_links(tmp_path: Path) -> None:
    (tmp_path / "other.md").write_text("# A page\n\n## Its `second` section (v2)!\n\n## Twice\n\n## Twice\n")
    page = tmp_path / "page.md"
    page.write_text(
        "# Title\n\n[ok](other.md) [ok](other.md#its-second-section-v2) [ok](other.md#twice-1) [ok](#title)\n"
        "[gone](missing.md) [bad anchor](other.md#nope) ![img](nope.png) [web](https://example.org/x.md)\n"
        "`[code](missing2.md)`\n\n    [indented](missing3.md)\n"
    )
    assert broken_links(page) == [
        "missing.md (no such file)",
        "other.md#nope (no heading #nope in other.md)",
        "nope.png (no such file)",
    ]


_MACHINE_PATH = re.compile(r"(?<![\w.])/(work|root|home)/|this session", re.IGNORECASE)
_ISSUE_NUMBER = re.compile(r"\bissues? #?\d+", re.IGNORECASE)


def _lines(path: Path) -> list[tuple[int, str]]:
    return list(enumerate(path.read_text(encoding="utf-8").splitlines(), 1))


def test_docs_name_no_machine_path_and_no_session() -> None:
    pages = [*ROOT.glob("docs/**/*.md"), *ROOT.glob("*.md"), *ROOT.glob("*/README.md")]
    found = [f"{p.relative_to(ROOT)}:{n}" for p in pages if p.name != "CHANGELOG.md" for n, line in _lines(p)
             if _MACHINE_PATH.search(line)]  # fmt: skip
    assert not found, found


def test_the_code_cites_no_issue_number() -> None:
    code = [p for folder in ("zedo_cli", "benchmarks", "experiments", "tests") for p in (ROOT / folder).rglob("*.py")
            if p != Path(__file__)]  # fmt: skip
    found = [f"{p.relative_to(ROOT)}:{n}" for p in code for n, line in _lines(p) if _ISSUE_NUMBER.search(line)]
    assert not found, found


def test_the_checks_see_what_they_look_for() -> None:
    assert _MACHINE_PATH.search("run it in /work/main first") and _MACHINE_PATH.search("measured this session")
    assert not _MACHINE_PATH.search("see docs/work/x.md")
    assert _ISSUE_NUMBER.search("(issue 38)") and not _ISSUE_NUMBER.search("the issue of scale")


def test_docs_prose_cites_no_issue_number() -> None:
    pages = [*ROOT.glob("docs/**/*.md"), ROOT / "README.md", *ROOT.glob("*/README.md")]
    found = [f"{p.relative_to(ROOT)}:{n}" for p in pages if p.name != "decisions.md" for n, line in _lines(p)
             if _ISSUE_NUMBER.search(line)]  # fmt: skip
    assert not found, found
