"""Every command shown to a user is run: the README and docs/ (shell, console and Python blocks),
the header comments of models/*.toml, and the docstrings and help texts of the package.

Commands run in a sandbox folder holding copies of ``models/``, ``ground_motions/`` and ``examples/``,
in the order the README shows them (the study before its queries).  A console block's
printed output is compared with what the command prints (a line ``...`` stands for
lines left out).  Benchmark commands (``python -m benchmarks.X``, ``python -m
benchmarks.canonical``) run for minutes or need the test-only records of ``../shared``:
they are checked to start and parse their options (``--help``), which a stale name
or option in the text would fail.
"""

from __future__ import annotations

import os
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
BIN = Path(sys.executable).parent
DOCS = [REPO / "README.md", *sorted((REPO / "docs").glob("*.md"))]
PLACEHOLDER = re.compile(r"\b[A-Z][A-Z_]{2,}\b(\.[a-z0-9]+)?")  # MODEL.toml, STUDY.h5, OUT, FILE ...
FENCE = re.compile(r"^```(\w*)\n(.*?)^```", re.S | re.M)


def _blocks(path: Path):
    """(language, text) of every fenced block of a Markdown file."""
    return [(m.group(1), m.group(2)) for m in FENCE.finditer(path.read_text(encoding="utf-8"))]


def _is_benchmark(cmd: str) -> bool:
    return bool(re.search(r"python3? -m (benchmarks\.|seispound\.bench)", cmd))


def _local(cmd: str) -> str:
    """The command with this environment's executables (the README's .venv/bin is the test's venv)."""
    parts = [p.strip() for p in cmd.split("&&")]
    parts = [p for p in parts if not (p.startswith("python3 -m venv") or "pip install" in p)]
    cmd = " && ".join(parts)
    cmd = re.sub(r"(^|\s|&& )\.venv/bin/", lambda m: m.group(1) + f"{BIN}/", cmd)
    cmd = re.sub(r"(^|&& )seispound ", lambda m: m.group(1) + f"{BIN}/seispound ", cmd)
    return re.sub(r"(^|&& )python3? ", lambda m: m.group(1) + f"{sys.executable} ", cmd)


def shell_commands(text: str) -> list[str]:
    """Commands of a bash block: non-comment lines, with trailing comments dropped."""
    out = []
    for line in text.replace("\\\n", " ").splitlines():  # a line ending in a backslash continues on the next
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        out.append(re.sub(r"\s+#\s.*$", "", line))
    return out


def console_commands(text: str) -> list[tuple[str, list[str]]]:
    """(command, shown output lines) of a console block: lines after ``$ `` and what follows them."""
    out = []
    for line in text.splitlines():
        if line.startswith("$ "):
            out.append((line[2:].strip(), []))
        elif out:
            out[-1][1].append(line)
    return out


def comment_commands(path: Path) -> list[str]:
    return [m.group(1).strip() for m in re.finditer(r"(?m)^#\s+(seispound .+)$", path.read_text(encoding="utf-8"))]


def docstring_commands(path: Path) -> list[str]:
    text = path.read_text(encoding="utf-8")
    found = re.findall(r"(?m)^\s*(?:\$ )?(seispound (?:run|study|query|plot|laws)\b[^\n`]*)$", text)
    return [c.strip() for c in found if not PLACEHOLDER.search(c)]


@pytest.fixture(scope="module")
def sandbox(tmp_path_factory):
    root = tmp_path_factory.mktemp("documented")
    for name in ("models", "ground_motions", "examples"):
        shutil.copytree(REPO / name, root / name)
    return root


def run(cmd: str, cwd: Path, timeout=600) -> subprocess.CompletedProcess:
    env = dict(os.environ, COLUMNS="200")
    proc = subprocess.run(_local(cmd), shell=True, cwd=cwd, capture_output=True, text=True, timeout=timeout, env=env)
    assert proc.returncode == 0, f"{cmd!r} exited {proc.returncode}:\n{proc.stderr[-2000:]}"
    return proc


def _matches(shown: list[str], printed: list[str]) -> bool:
    """True if the printed lines equal the shown ones, where a shown line ``...`` (or ending in ...) skips."""
    pattern = "".join(r"(.*\n)*?" if s.strip() == "..." else re.escape(s.rstrip()).replace(r"\.\.\.", ".*") + r"\n"
                      for s in shown if s.strip())
    return re.fullmatch(pattern + r"(.*\n)*", "\n".join(p.rstrip() for p in printed if p.strip()) + "\n") is not None


def readme_steps():
    """Every command and Python block of the README, in order: ('shell'|'console'|'python', cmd, shown)."""
    steps = []
    for lang, text in _blocks(REPO / "README.md"):
        if lang == "bash":
            steps += [("shell", c, None) for c in shell_commands(text) if not PLACEHOLDER.search(c)]
        elif lang == "console":
            steps += [("console", c, shown) for c, shown in console_commands(text) if not PLACEHOLDER.search(c)]
        elif lang == "python":
            steps.append(("python", text, None))
    return steps


def test_readme_shows_commands():
    kinds = [k for k, _, _ in readme_steps()]
    assert kinds.count("shell") >= 3 and kinds.count("python") >= 1


def test_readme_commands_run_in_order(sandbox):
    """The README as a user would follow it: set-up, first script, run, study, queries, plots."""
    for kind, cmd, shown in readme_steps():
        if kind == "python":
            proc = subprocess.run([sys.executable, "-c", cmd], cwd=sandbox, capture_output=True, text=True,
                                  timeout=600)
            assert proc.returncode == 0, f"README Python block failed:\n{cmd}\n{proc.stderr[-3000:]}"
            continue
        if _is_benchmark(cmd):
            module = re.search(r"-m ([\w.]+)", cmd).group(1)
            run(f"cd {REPO} && python -m {module} --help", sandbox, timeout=120)
            continue
        if "pytest" in cmd:  # the test command itself: CI runs it verbatim (.ci/run)
            ci = (REPO / ".ci" / "run").read_text(encoding="utf-8")
            test_cmd = cmd[cmd.index("-m pytest"):]
            assert f"python {test_cmd}\n" in ci, (cmd, ci)
            continue
        proc = run(cmd, sandbox)
        if kind == "console" and shown and any(s.strip() for s in shown):
            printed = (Path(sandbox, shlex.split(cmd)[1]).read_text() if cmd.startswith("cat ")
                       else proc.stdout).splitlines()
            assert _matches(shown, printed), f"{cmd!r} printed\n{proc.stdout}\nbut the README shows\n" + \
                "\n".join(shown)


@pytest.mark.parametrize("model", sorted(p.name for p in (REPO / "models").glob("*.toml")))
def test_model_file_comments_run(sandbox, model):
    for cmd in comment_commands(REPO / "models" / model):
        run(cmd, sandbox)


def _sources():
    return sorted(p for d in ("seispound", "benchmarks") for p in (REPO / d).rglob("*.py"))


def test_docstring_commands_run(sandbox):
    """``seispound ...`` lines in docstrings and help texts (placeholders such as STUDY.h5 left out)."""
    seen = 0
    if not (sandbox / "gap_study.h5").exists():
        run("seispound study models/gap_study.toml -o gap_study.h5 -q", sandbox)
    if not (sandbox / "study.h5").exists():  # the generic name the query help uses
        shutil.copyfile(sandbox / "gap_study.h5", sandbox / "study.h5")
    for path in _sources():
        for cmd in docstring_commands(path):
            run(cmd, sandbox)
            seen += 1
    assert seen >= 3


def test_benchmark_commands_start():
    """Each ``python -m X`` named in a docstring or the docs parses its options."""
    modules = set()
    for path in [*_sources(), *DOCS]:
        modules |= set(re.findall(r"python3? -m ((?:benchmarks|seispound)\.[\w.]+)", path.read_text(encoding="utf-8")))
    assert "benchmarks.canonical" in modules
    for module in sorted(modules):
        proc = subprocess.run([sys.executable, "-m", module, "--help"], cwd=REPO, capture_output=True, text=True,
                              timeout=120)
        assert proc.returncode == 0, f"python -m {module} --help: {proc.stderr[-1500:]}"
