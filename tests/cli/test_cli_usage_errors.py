"""Usage mistakes are one line with a hint and exit code 2, off a terminal and on one:
never typer's boxed panel, on any command. Run as a user runs zedo, in a subprocess,
with stderr a pipe and then a pseudo-terminal."""

from __future__ import annotations

import json
import os
import pty
import select
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
ENV = {**os.environ, "PYTHONPATH": str(ROOT), "COLUMNS": "80", "TERM": "xterm"}
ZEDO = [sys.executable, "-m", "zedo_cli"]
BOX = set("╭╮╰╯│─")

# (arguments, what the one line says)
CASES = [
    (["lift", "kp.json", "--ouput", "y.json"], "zedo: error: no such option --ouput; did you mean --output?"),
    (["lift", "kp.json", "--image-size", "640", "-o", "y.json"],
     "zedo: error: --image-size takes two numbers, WIDTH HEIGHT, but got '640 -o': -o was read as one of its "
     "numbers; give both numbers, e.g. --image-size 1280 720"),
    (["lift", "--video", "clip.mp4"],
     "zedo: error: missing KEYPOINTS; zedo needs 2D keypoints from a detector (COCO, OpenPose, MMPose, AlphaPose, "
     "zedo 2D JSON / JSON Lines), also with --video: see docs/inputs.md"),
    (["lift", "kp.json", "--steps", "many"], "zedo: error: --steps: expected an integer, got 'many'"),
    (["lift", "kp.json", "--preset"], "zedo: error: option --preset needs a value"),
    (["lft", "kp.json"], "zedo: error: no such command lft; did you mean lift?"),
    (["analyze", "--json"], "zedo: error: missing RESULTS; analyze reads zedo results: run zedo lift"),
    (["render", "-o", "x.mp4"], "zedo: error: missing RESULT; render draws a zedo result: run zedo lift"),
    (["export", "r.zedo.json", "--marker-axis", "level"], "did you mean --marker-axes?"),
    (["calibrate", "a.png", "--square", "x"], "zedo: error: --square: expected a number, got 'x'"),
    (["evaluate", "r.json", "--bogus"], "zedo: error: no such option --bogus; zedo evaluate --help lists every option"),
]  # fmt: skip


# One interpreter runs every case, as `zedo ARGS` would (a fresh process per case costs a second each):
# before each case a marker line on stderr, after it the exit code.
RUN_CASES = """
import json, sys
from zedo_cli.cli import app
for args in json.loads(sys.argv[1]):
    sys.stderr.write("@@case\\n")
    sys.stderr.flush()
    try:
        app(args, prog_name="zedo")
        code = 0
    except SystemExit as exc:
        code = exc.code
    sys.stderr.flush()
    sys.stderr.write(f"@@exit {code}\\n")
    sys.stderr.flush()
"""


def _cases(text: str) -> list[tuple[int, str]]:
    """(exit code, what was printed) of every case, from the runner's output."""
    out = []
    for part in text.replace("\r\n", "\n").split("@@case\n")[1:]:
        body, _, code = part.rpartition("@@exit ")
        out.append((int(code.split()[0]), body))
    return out


def _check(text: str, expected: str) -> None:
    lines = [line for line in text.splitlines() if line.strip()]
    assert len(lines) == 1, text
    assert lines[0].startswith("zedo: error: ") and expected in lines[0], lines[0]
    assert not BOX & set(text) and "Usage:" not in text and "Traceback" not in text, text
    assert "\x1b[" not in text, text  # no colour, on a terminal either


def test_off_a_terminal(tmp_path: Path) -> None:
    args = [a for a, _ in CASES]
    done = subprocess.run([sys.executable, "-c", RUN_CASES, json.dumps(args)], capture_output=True, text=True,
                          env=ENV, cwd=tmp_path, timeout=300)  # fmt: skip
    assert done.stdout == ""
    results = _cases(done.stderr)
    assert len(results) == len(CASES), done.stderr
    for (args, expected), (code, text) in zip(CASES, results, strict=True):
        assert code == 2, (args, text)
        _check(text, expected)


def _on_a_terminal(argv: list[str], cwd: Path) -> tuple[int, str]:
    """Run `argv` with stdout and stderr on a pseudo-terminal; its exit code and what it printed."""
    leader, follower = pty.openpty()
    proc = subprocess.Popen(argv, stdin=subprocess.DEVNULL, stdout=follower, stderr=follower, env=ENV, cwd=cwd,
                            close_fds=True)  # fmt: skip
    os.close(follower)
    out = b""
    while True:
        ready, _, _ = select.select([leader], [], [], 300)
        if not ready:
            break
        try:
            chunk = os.read(leader, 4096)
        except OSError:  # the terminal closed: the process has exited
            break
        if not chunk:
            break
        out += chunk
    os.close(leader)
    return proc.wait(timeout=300), out.decode("utf-8", errors="replace")


def test_on_a_terminal(tmp_path: Path) -> None:
    """The same one line, no box, no colour codes, with a terminal as stderr; and `zedo` itself
    (`python -m zedo_cli`) run on a terminal for one case."""
    code, text = _on_a_terminal([sys.executable, "-c", RUN_CASES, json.dumps([a for a, _ in CASES])], tmp_path)
    assert code == 0, text
    results = _cases(text)
    assert len(results) == len(CASES), text
    for (args, expected), (code, printed) in zip(CASES, results, strict=True):
        assert code == 2, (args, printed)
        _check(printed, expected)
    code, text = _on_a_terminal([*ZEDO, *CASES[0][0]], tmp_path)
    assert code == 2
    _check(text.replace("\r\n", "\n"), CASES[0][1])
