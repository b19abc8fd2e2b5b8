"""Cold start (docs/lifting.md, "Start-up"): help and option errors answer without loading torch,
`zedo --help` imports no command module (nor numpy, pydantic or the analysis package), and
lifting never loads torch's compiler stack (torch._dynamo, which creating a torch.optim
optimiser imports: about 0.8 s)."""

from __future__ import annotations

import inspect
import json
import subprocess
import sys
from pathlib import Path

import pytest
import typer

from zedo_cli.cli import COMMANDS, PANELS, app

HEAVY = ("torch", "matplotlib", "scipy", "cv2", "safetensors")
# What the list of commands must not import: each of these takes tens to hundreds of milliseconds.
NOT_FOR_THE_LIST = ("numpy", "pydantic", "zedo_cli.analysis", "zedo_cli.formats", "zedo_cli.data", "zedo_cli.lifting")

# Runs the CLI in a fresh interpreter, then prints which modules it loaded.
RUN_AND_LIST = """
import json, sys
from zedo_cli.cli import app
try:
    app(sys.argv[1:], prog_name="zedo")
except SystemExit:
    pass
print(json.dumps(sorted(sys.modules)))
"""


def loaded_modules(*args: str) -> set[str]:
    out = subprocess.run([sys.executable, "-c", RUN_AND_LIST, *args], capture_output=True, text=True, check=True)
    return set(json.loads(out.stdout.strip().splitlines()[-1]))


# Every command's --help in one fresh interpreter, one after the other: the heavy modules loaded
# after each are printed, so a command that loads one is named (one interpreter, not fourteen).
EVERY_HELP = """
import json, sys
from zedo_cli.cli import app
heavy = json.loads(sys.argv[1])
loaded = {}
for args in json.loads(sys.argv[2]):
    try:
        app(args, prog_name="zedo")
    except SystemExit:
        pass
    loaded[" ".join(args)] = sorted(m for m in heavy if m in sys.modules)
print(json.dumps(loaded))
"""


def test_help_loads_no_heavy_library() -> None:
    helps = [["--help"], *[[name, "--help"] for name in COMMANDS]]
    out = subprocess.run([sys.executable, "-c", EVERY_HELP, json.dumps(HEAVY), json.dumps(helps)],
                         capture_output=True, text=True, check=True)  # fmt: skip
    loaded = json.loads(out.stdout.strip().splitlines()[-1])
    assert list(loaded) == [" ".join(a) for a in helps]
    assert not any(loaded.values()), {k: v for k, v in loaded.items() if v}


def test_the_list_of_commands_imports_no_command() -> None:
    commands = {f"zedo_cli.cli.{entry.module}" for entry in COMMANDS.values()}
    for args in (["--help"], []):  # the list of commands, also of a bare `zedo`
        loaded = loaded_modules(*args)
        assert sorted(m for m in loaded if m.startswith(NOT_FOR_THE_LIST)) == [], args
        assert not loaded & commands, (args, sorted(loaded & commands))
    # an unknown command's did-you-mean reads the table's names (typer's option parsing loads pydantic)
    loaded = loaded_modules("lifft")
    assert not loaded & commands, sorted(loaded & commands)


def test_a_command_imports_only_its_own_module() -> None:
    loaded = loaded_modules("schema", "--help")
    assert "zedo_cli.cli.schema" in loaded
    others = {f"zedo_cli.cli.{entry.module}" for entry in COMMANDS.values()} - {"zedo_cli.cli.schema"}
    assert not loaded & others, sorted(loaded & others)
    assert "zedo_cli.analysis" not in loaded


def test_the_summaries_are_the_docstrings_first_lines() -> None:
    group = typer.main.get_command(app)
    ctx = group.make_context("zedo", ["--help"], resilient_parsing=True)
    assert group.list_commands(ctx) == list(COMMANDS) == [name for panel in PANELS.values() for name in panel]
    for name, entry in COMMANDS.items():
        function = entry.load()
        assert entry.summary == inspect.getdoc(function).splitlines()[0], name
        command = group.get_command(ctx, name)  # what `zedo --help` showed when it imported every command
        assert command.name == name
        assert command.rich_help_panel == group.commands.panel(name), name
        assert entry.summary == command.get_short_help_str(limit=300), name
    assert group.get_command(ctx, "no-such-command") is None


def test_option_errors_answer_before_torch_loads(tmp_path: Path) -> None:
    loaded = loaded_modules("lift", str(tmp_path / "x.json"), "--preset", "nonsense")
    assert "torch" not in loaded


@pytest.mark.parametrize(
    "args",
    [
        ["evaluate", "r.json", "--gt", "t.npz", "--protocol", "coco"],
        ["benchmark", "--scale", "0"],
        ["benchmark-symmetry", "--syrip-dir", "syrip", "--preset", "quick"],
    ],
)
def test_the_evaluation_commands_option_errors_answer_before_torch_loads(args: list[str]) -> None:
    assert "torch" not in loaded_modules(*args)


def test_lifting_does_not_load_the_compiler_stack(tmp_path: Path) -> None:
    example = Path(__file__).resolve().parents[2] / "examples" / "prior_samples_coco.json"
    loaded = loaded_modules("lift", str(example), "-o", str(tmp_path / "out.json"), "--quiet")
    assert (tmp_path / "out.json").is_file()
    assert "torch" in loaded
    assert "torch._dynamo" not in loaded
    # nor what this lift does not use: the result schema, the analysis, calibration files, a live bar
    unused = ("zedo_cli.analysis", "zedo_cli.formats.result_schema", "zedo_cli.camera.files", "rich.progress")
    assert sorted(loaded & set(unused)) == []
