"""`--help` that fits a screen: the options of a command grouped in panels (typer's
`rich_help_panel`), option names never cut short, paragraphs rewrapped to the terminal, and a
short usage with a hint when a command is run without arguments."""

from __future__ import annotations

import inspect
import sys
import textwrap
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import typer
from rich.console import Console, Group
from rich.panel import Panel
from rich.table import Table
from rich.text import Text
from typer.core import TyperArgument, TyperCommand, TyperGroup

from .lazy_commands import LazyCommand, LazyCommands
from .usage import Abort, ClickException, usage_error_line

# typer's click objects (its own vendored click in recent typer versions) are typed Any here: the
# help only reads their documented attributes (params, opts, help, default, nargs, metavar).
DEFAULT_PANEL = "Options"
_TYPE_NAMES = {"str": "TEXT", "path": "PATH", "float": "FLOAT", "int": "INT", "bool": ""}


def _argument_name(param: Any) -> str:
    """`KEYPOINTS...`: an argument by name, in capitals, with ... when it takes several."""
    return (param.metavar or param.name or "").upper() + ("..." if param.nargs == -1 else "")


def usage_line(command: Any, ctx: Any) -> str:
    """`zedo lift [OPTIONS] KEYPOINTS...`: arguments by name, in capitals."""
    parts = [ctx.command_path, "[OPTIONS]"]
    for param in command.params:
        if isinstance(param, TyperArgument) and not getattr(param, "hidden", False):
            name = _argument_name(param)
            parts.append(name if param.required else f"[{name}]")
    return " ".join(parts)


def _metavar(param: Any, ctx: Any) -> str:
    if getattr(param, "is_flag", False):
        return ""
    if param.metavar:
        return param.metavar
    shown = (param.display_type_rich(ctx) or "").strip("<>.")  # type: ignore[attr-defined]
    if shown.startswith("list[") and shown.endswith("]"):  # a repeatable option: its item's type
        shown = shown[5:-1]
    return " ".join(_TYPE_NAMES.get(part, part.upper()) for part in shown.split(","))


def _names(param: Any, ctx: Any) -> str:
    """`-o, --output PATH`: the short names and the first long name (later long names, such as
    an older spelling kept working, are not shown)."""
    if isinstance(param, TyperArgument):
        return _argument_name(param)
    short = [o for o in param.opts if not o.startswith("--")]
    long = [o for o in param.opts if o.startswith("--")][:1]
    return " ".join([", ".join(short + long), _metavar(param, ctx)]).strip()


def _default(param: Any) -> str:
    shown = getattr(param, "show_default", True)
    value = param.default
    if not shown or value is None or value is False or getattr(param, "is_flag", False) or callable(value):
        return ""
    if isinstance(value, (list, tuple)):
        value = " ".join(str(v) for v in value)
    return f" [default: {value}]"


def _paragraphs(doc: str, width: int) -> list[Text]:
    """The docstring's paragraphs, rewrapped; indented lines (examples) kept as commands, a long
    one continued on the next line with a shell backslash, so that it still pastes into a shell."""
    out: list[Text] = []
    for block in inspect.cleandoc(doc).split("\n\n"):
        lines = block.splitlines()
        if lines and all(line.startswith(" ") for line in lines):
            out.append(Text("\n".join(_command_lines(line, width) for line in lines)))
        else:
            out.append(Text(" ".join(line.strip() for line in lines)))
    return out


def _command_lines(line: str, width: int) -> str:
    if len(line) <= width:
        return line
    indent = line[: len(line) - len(line.lstrip())]
    pieces = textwrap.wrap(line.strip(), width=width - len(indent) - 2, break_long_words=False,
                           break_on_hyphens=False, subsequent_indent="    ")  # fmt: skip
    return " \\\n".join(indent + piece for piece in pieces)


def _panels(command: Any, ctx: Any) -> dict[str, list[Any]]:
    panels: dict[str, list[Any]] = {}
    for param in command.get_params(ctx):
        if getattr(param, "hidden", False):
            continue
        panel = getattr(param, "rich_help_panel", None) or DEFAULT_PANEL
        panels.setdefault(panel, []).append(param)
    return panels


def render_help(command: Any, ctx: Any, console: Console) -> str:
    """The whole help of `command`, in one width (the terminal's, else 80 columns), without
    trailing blanks."""
    with console.capture() as captured:
        _print_help(command, ctx, console)
    return "\n".join(line.rstrip() for line in captured.get().splitlines()) + "\n"


def _print_help(command: Any, ctx: Any, console: Console) -> None:
    usage = f"{ctx.command_path} [OPTIONS] COMMAND [ARGS]..." if isinstance(command, TyperGroup) else None
    body: list[Any] = [Text(f"Usage: {usage or usage_line(command, ctx)}", style="bold"), Text("")]
    for paragraph in _paragraphs(command.help or "", console.width):
        body += [paragraph, Text("")]
    console.print(Group(*body))
    for title, params in _panels(command, ctx).items():
        rows = []
        for param in params:
            help_text = (getattr(param, "help", None) or "") + _default(param)
            if isinstance(param, TyperArgument) and param.required:
                help_text += " [required]"
            rows.append((_names(param, ctx), help_text))
        console.print(_panel(title, rows))
    if isinstance(command, ZedoGroup):  # the commands in their panels, in order, from the table: none imported
        panels: dict[str, list[tuple[str, str]]] = {}
        for name in command.list_commands(ctx):
            title = command.commands.panel(name) or "Commands"
            panels.setdefault(title, []).append((name, command.commands.summary(name)))
        for title, rows in panels.items():
            console.print(_panel(title, rows))


def _panel(title: str, rows: list[tuple[str, str]]) -> Panel:
    """A titled box of two columns: names never wrapped, their help wrapped to what is left."""
    table = Table.grid(padding=(0, 2))
    table.add_column(no_wrap=True, style="bold cyan")
    table.add_column(ratio=1, overflow="fold")
    for name, text in rows:
        table.add_row(name, Text(text))
    return Panel(table, title=title, title_align="left", border_style="dim")


def short_usage(command: Any, ctx: Any) -> str:
    """What a command run without arguments prints: its usage, what it does, one example, and
    where the rest is."""
    doc = inspect.cleandoc(command.help or "")
    lines = [f"Usage: {usage_line(command, ctx)}", "", doc.splitlines()[0] if doc else ""]
    examples = doc.split("Example", 1)[1].splitlines()[1:] if "Example" in doc else []
    first = next((line.strip() for line in examples if line.strip()), None)
    if first:
        lines += ["", f"Example: {first}"]
    lines += ["", f"Try '{ctx.command_path} --help' for every option."]
    return "\n".join(lines)


class _ZedoHelp:
    """zedo's help layout for a typer command or group (mixed in before the typer class)."""

    def format_help(self, ctx: Any, formatter: Any) -> None:
        formatter.write(render_help(self, ctx, Console(highlight=False)))


def command_from_function(name: str, function: Callable[..., Any], panel: str, rich_markup_mode: Any) -> Any:
    """The click command typer makes of `function` (its options from the annotations, its help
    from the docstring), as `app.command(name, ...)` registers it, with zedo's help layout."""
    one = typer.Typer(add_completion=False, pretty_exceptions_enable=False, rich_markup_mode=rich_markup_mode)
    one.command(name, no_args_is_help=True, cls=ZedoCommand, rich_help_panel=panel)(function)
    return typer.main.get_command(one)


class ZedoGroup(_ZedoHelp, TyperGroup):
    """The `zedo` group, with the same help layout as its commands, and usage errors of every
    command as one line (cli/usage.py) instead of typer's boxed panel. Its commands are the
    subclass's `panels` (cli/__init__.py), each imported and made a click command only when it is
    looked up (cli/lazy_commands.py)."""

    panels: Mapping[str, Mapping[str, LazyCommand]] = {}

    def __init__(self, **attrs: Any) -> None:
        super().__init__(**attrs)
        mode = self.rich_markup_mode
        self.commands = LazyCommands(
            self.panels, lambda name, function, panel: command_from_function(name, function, panel, mode)
        )
        for name, command in attrs.get("commands", {}).items():  # any typer registered the usual way
            self.commands[name] = command

    def list_commands(self, ctx: Any) -> list[str]:
        return list(self.commands)  # the names only (typer's own reads every command)

    def main(self, args: Sequence[str] | None = None, prog_name: str | None = None, complete_var: str | None = None,
             standalone_mode: bool = True, **extra: Any) -> Any:  # fmt: skip
        if not standalone_mode:
            return super().main(args, prog_name, complete_var, standalone_mode, **extra)
        words = list(sys.argv[1:] if args is None else args)
        try:
            code = super().main(words, prog_name, complete_var, False, **extra)
        except ClickException as exc:
            sys.stderr.write(usage_error_line(exc, words) + "\n")
            sys.exit(exc.exit_code)
        except Abort:  # end of input at a prompt (zedo asks none; click's own)
            sys.stderr.write("zedo: interrupted\n")
            sys.exit(1)
        sys.exit(code if isinstance(code, int) else 0)

    def parse_args(self, ctx: Any, args: list[str]) -> list[str]:
        if not args and self.no_args_is_help and not ctx.resilient_parsing:
            sys.stdout.write(ctx.get_help() + "\n")  # the list of commands, as --help (typer drops it otherwise)
            raise typer.Exit(2)
        return super().parse_args(ctx, args)


class ZedoCommand(_ZedoHelp, TyperCommand):
    """A typer command with zedo's help layout (see the module's docstring)."""

    def parse_args(self, ctx: Any, args: list[str]) -> list[str]:
        if not args and self.no_args_is_help and not ctx.resilient_parsing:
            sys.stderr.write(short_usage(self, ctx) + "\n")
            raise typer.Exit(2)  # a usage error: the required arguments are missing
        if any(p.name == "config" for p in self.params):
            from .config import config_argument, load_config

            path = config_argument(args)
            if path is not None:  # its values are the defaults the command line overrides
                load_config(ctx, self, path)
        try:
            return super().parse_args(ctx, args)
        except ClickException as exc:  # the parser's own errors come without the command: named in the message
            if getattr(exc, "ctx", None) is None:
                exc.ctx = ctx
            raise
