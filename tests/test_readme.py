"""The README's code and commands stay true, and the documentation's links and commands
point at things that exist."""

from __future__ import annotations

import contextlib
import io
import re
from importlib import metadata
from pathlib import Path

import pytest

import armik
from tests.doc_blocks import python_blocks, run

ROOT = Path(__file__).parents[1]
README = (ROOT / "README.md").read_text()
DOCS = ROOT / "docs"
PAGES = sorted(DOCS.glob("*.md")) if DOCS.is_dir() else []
GUIDES = [p for p in (ROOT / "CONTRIBUTING.md", ROOT / "CHANGELOG.md") if p.exists()]
needs_docs = pytest.mark.skipif(not PAGES, reason="docs/ is not part of this tree (an sdist)")


def section(text: str, heading: str) -> str:
    """The text under a '## heading' up to the next '## '."""
    match = re.search(rf"^## {re.escape(heading)}\n(.*?)(?=^## |\Z)", text, flags=re.S | re.M)
    assert match, f"no '## {heading}' section"
    return match.group(1)


def test_python_use_block_runs():
    blocks = python_blocks(README)
    assert blocks, "README has no python block"
    out = run(blocks[0], "README.md")
    assert "elbow-up" in out and "True converged dls" in out


@pytest.mark.parametrize("index", range(1, len(python_blocks(README))))
def test_every_readme_python_block_runs(index, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    out = run(python_blocks(README)[index], f"README.md block {index}")
    assert "True" in out  # each block prints at least one verified success


def test_quick_start_covers_the_api():
    code = "".join(python_blocks(README))
    for name in (
        "armik.load(",
        "tip=",
        "base=",
        "tip_offset=",
        "locked=",
        ".with_limits(",
        ".with_locked(",
        ".solve(",
        ".solve_all(",
        ".solve_batch(",
        ".solve_path(",
        "weights=",
    ):
        assert name in code, f"the README's code does not show {name}"


def test_two_commands_between_markers():
    for marker, words in (("demo-command", "armik demo"), ("test-command", "pytest")):
        block = re.search(rf"<!-- {marker} -->\n```\n(.*?)\n```\n<!-- /{marker} -->", README)
        assert block and words in block.group(1) and "pip install" in block.group(1)


def test_solver_table_lists_every_solver():
    rows = re.findall(r"^\| `(\w+)` \|", section(README, "Solvers"), flags=re.M)
    assert rows == armik.solvers()


def test_every_bundled_arm_is_listed():
    text = section(README, "Bundled arms")
    missing = [name for name in armik.robots() if f"`{name}`" not in text]
    assert not missing, f"README's bundled arms do not name {missing}"


def _main():
    (script,) = [e for e in metadata.entry_points(group="console_scripts") if e.name == "armik"]
    return script.load()


def _subcommands(text: str) -> set[str]:
    """The X of every `armik X` in code: a line of a fenced block, or an inline span."""
    fenced = re.findall(r"```\w*\n(.*?)```", text, flags=re.S)
    lines = re.findall(r"^armik ([a-z]+)\b", "\n".join(fenced), flags=re.M)
    spans = re.findall(r"`armik ([a-z]+)\b", re.sub(r"```.*?```", "", text, flags=re.S))
    return set(lines) | set(spans)


def test_readme_commands_exist():
    commands = _subcommands(section(README, "Command line"))
    assert {"solve", "batch", "reach", "bench"} <= commands
    main = _main()
    for command in sorted(commands):
        with pytest.raises(SystemExit) as stop, contextlib.redirect_stdout(io.StringIO()):
            main([command, "--help"])
        assert stop.value.code == 0, f"'armik {command}' is not a command"


def test_readme_names_every_command():
    """Each command of ``armik --help`` is in the README's Command line section."""
    from armik.tools.cli.main import _parser

    parser = _parser()
    (commands,) = [a.choices for a in parser._actions if a.choices and "solve" in a.choices]
    missing = sorted(set(commands) - _subcommands(section(README, "Command line")))
    assert not missing, f"the README's Command line does not name: {missing}"


@needs_docs
def test_docs_commands_exist():
    main = _main()
    text = "\n".join(page.read_text() for page in PAGES)
    for command in sorted(_subcommands(text)):
        with pytest.raises(SystemExit) as stop, contextlib.redirect_stdout(io.StringIO()):
            main([command, "--help"])
        assert stop.value.code == 0, f"docs/ cite 'armik {command}', which is not a command"
    scripts = set(re.findall(r"benchmarks/(\w+\.py)", text))
    assert scripts, "docs/ cite no benchmark script"
    missing = sorted(s for s in scripts if not (ROOT / "benchmarks" / s).exists())
    assert not missing, f"docs/ cite benchmark scripts that do not exist: {missing}"


def _slug(heading: str) -> str:
    """GitHub's anchor for a heading: lower case, punctuation dropped, spaces to '-'."""
    text = re.sub(r"[^\w\- ]", "", heading.strip().lower())
    return text.replace(" ", "-")


def _anchors(path: Path) -> set[str]:
    text = re.sub(r"```.*?```", "", path.read_text(), flags=re.S)
    return {_slug(h) for h in re.findall(r"^#+ (.*)$", text, flags=re.M)}


@needs_docs
@pytest.mark.parametrize(
    "page", [ROOT / "README.md", *GUIDES, *PAGES], ids=lambda p: str(p.relative_to(ROOT))
)
def test_links_resolve(page):
    text = re.sub(r"```.*?```", "", page.read_text(), flags=re.S)  # code is not links
    text = re.sub(r"`[^`\n]*`", "", text)
    for target in re.findall(r"\]\(([^)\s]+)\)", text):
        if re.match(r"[a-z]+://", target):
            continue
        file, _, anchor = target.partition("#")
        path = (page.parent / file).resolve() if file else page
        assert path.exists(), f"{page.name}: link to missing {target}"
        if anchor and path.suffix == ".md":
            assert anchor in _anchors(path), f"{page.name}: no heading for {target}"


@needs_docs
def test_readme_links_every_docs_page():
    for page in PAGES:
        assert f"docs/{page.name}" in README, f"README does not link docs/{page.name}"


@needs_docs
def test_readme_headline_numbers_are_in_performance_page():
    numbers = re.findall(r"\d+(?:[ .]\d+)*(?:e-?\d+)?", section(README, "Performance"))
    assert numbers
    performance = (DOCS / "performance.md").read_text()
    missing = [n for n in numbers if n not in performance]
    assert not missing, f"README's headline numbers not in docs/performance.md: {missing}"


def _flags(main, command: str) -> set[str]:
    """The long options `armik COMMAND --help` lists."""
    out = io.StringIO()
    with pytest.raises(SystemExit), contextlib.redirect_stdout(out):
        main([command, "--help"])
    return set(re.findall(r"(--[a-z][\w-]*)", out.getvalue()))


def _command_lines(text: str) -> list[tuple[str, str]]:
    """(command, line) for every `armik X ...` of the text: a fenced line and the indented
    lines that continue it, or an inline span; comments after '#' left out."""
    found = []
    for block in re.findall(r"```\w*\n(.*?)```", text, flags=re.S):
        command = None
        for line in block.splitlines():
            start = re.match(r"\s*(?:\$ )?armik ([a-z]+)\b", line)
            if start:
                command = start.group(1)
            elif not (command and re.match(r"\s+[\[-]", line)):
                command = None
            if command:
                found.append((command, line.split("#")[0]))
    for span in re.findall(r"`armik ([a-z]+)([^`]*)`", re.sub(r"```.*?```", "", text, flags=re.S)):
        found.append(span)
    return found


@needs_docs
def test_docs_command_flags_exist():
    """Every --flag on an `armik X` line of the README and docs/ is one of X's."""
    main = _main()
    known: dict[str, set[str]] = {}
    wrong = []
    for page in [ROOT / "README.md", *PAGES]:
        for command, line in _command_lines(page.read_text()):
            flags = known.setdefault(command, _flags(main, command))
            wrong += [
                f"{page.name}: armik {command} has no {flag} ({line.strip()})"
                for flag in re.findall(r"(?<![\w-])(--[a-z][\w-]*)", line)
                if flag not in flags
            ]
    assert len(known) >= 10, f"too few commands found: {sorted(known)}"
    assert not wrong, "\n".join(wrong)
