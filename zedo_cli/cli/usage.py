"""Usage errors (an unknown option, a missing argument, a value that is not a number) as one line,
on a terminal or not: `zedo: error: WHAT; HINT`, exit code 2 (docs/cli.md).

click (typer's parser) raises a `UsageError` for these and typer prints it as a boxed Rich panel
with the usage above it. `ZedoGroup.main` (cli/help.py) catches every click error of every
command instead and prints `usage_error_line(...)`: the message, then a hint where zedo knows a
better one than the help (the option meant, what a two-number option takes, where the keypoints
come from).
"""

from __future__ import annotations

import difflib
import re
from collections.abc import Sequence
from typing import Any

import typer

try:  # typer >= 0.2x vendors click as typer._click; older versions use click itself
    from typer._click.exceptions import ClickException  # type: ignore[import-not-found]
except ImportError:  # pragma: no cover - depends on the installed typer
    from click.exceptions import ClickException  # type: ignore[no-redef]

Abort = typer.Abort  # click's Abort, or typer's own in the versions that vendor click
__all__ = ["Abort", "ClickException", "usage_error_line"]

# A missing argument's hint, by command and argument: what the command needs and where it comes from.
ARGUMENT_HINTS = {
    ("lift", "keypoints"): "zedo needs 2D keypoints from a detector (COCO, OpenPose, MMPose, AlphaPose, "
    "zedo 2D JSON / JSON Lines), also with --video: see docs/inputs.md",
    ("analyze", "results"): "analyze reads zedo results: run zedo lift on the 2D keypoints first",
    ("render", "result"): "render draws a zedo result: run zedo lift on the 2D keypoints first",
    ("export", "result"): "export converts a zedo result: run zedo lift on the 2D keypoints first",
}


def command_name(ctx: Any) -> str:
    """`zedo lift` (whatever the program was called: `python -m zedo_cli` too)."""
    names = []
    while ctx is not None:
        names.append(ctx.info_name)
        ctx = ctx.parent
    return " ".join(["zedo", *reversed(names[:-1])])


def _help_hint(ctx: Any) -> str:
    name = command_name(ctx) if ctx is not None else "zedo"
    return (
        f"{name} --help lists every option" if ctx is not None and ctx.parent else f"{name} --help lists the commands"
    )


def _option_names(ctx: Any) -> list[str]:
    """The option names a user sees in the command's help (not hidden ones, nor older spellings)."""
    names: list[str] = []
    for param in ctx.command.get_params(ctx):
        if getattr(param, "param_type_name", "") != "option" or getattr(param, "hidden", False):
            continue
        names += [o for o in param.opts if not o.startswith("--")] + [o for o in param.opts if o.startswith("--")][:1]
    return names


def _lower_first(text: str) -> str:
    return text[:1].lower() + text[1:] if text[:2] != text[:2].upper() else text


def _raw_values(args: Sequence[str], option: str, count: int) -> list[str]:
    """The `count` words after `option` on the command line (as typed), or after `option=`."""
    for i, word in enumerate(args):
        if word == option:
            return list(args[i + 1 : i + 1 + count])
        if word.startswith(option + "="):
            return [word.split("=", 1)[1], *args[i + 1 : i + count]]
    return []


# What an option of several values looks like when given right (the hint of a bad value).
VALUE_EXAMPLES = {"--image-size": "1280 720", "--principal-point": "640 360"}
_COUNTS = {2: "two", 3: "three", 4: "four"}


def _bad_value(exc: Any, args: Sequence[str]) -> tuple[str, str] | None:
    """The message and hint for an option of several values (`--image-size WIDTH HEIGHT`) given
    something else, typically too few numbers so that the next option was read as one of its
    values (`--image-size 640 -o y.json`); None for another bad value."""
    param = getattr(exc, "param", None)
    if param is None or getattr(param, "param_type_name", "") != "option" or (param.nargs or 1) < 2:
        return None
    option = next((o for o in param.opts if o.startswith("--")), param.opts[0])
    metavar = param.metavar or " ".join(["VALUE"] * param.nargs)
    given = _raw_values(args, option, param.nargs)
    message = f"{option} takes {_COUNTS.get(param.nargs, param.nargs)} numbers, {metavar}"
    if given:
        message += f", but got {' '.join(given)!r}"
    swallowed = [w for w in given if w.startswith("-") and not _is_number(w)]
    if swallowed:
        message += f": {swallowed[0]} was read as one of its numbers"
    example = VALUE_EXAMPLES.get(option)
    hint = ("give both numbers" if param.nargs == 2 else f"give all {param.nargs} numbers") + (
        f", e.g. {option} {example}" if example else ""
    )
    return message, hint


# pydantic's words for the type a value should have (typer converts option values with it)
_EXPECTED = {"a valid integer": "an integer", "a valid number": "a number", "a valid boolean": "true or false"}


def _invalid_value(exc: Any, args: Sequence[str]) -> str | None:
    """`--steps: expected an integer, got 'abc'` for a value that does not convert."""
    param = getattr(exc, "param", None)
    if param is None or getattr(param, "param_type_name", "") != "option":
        return None
    option = next((o for o in param.opts if o.startswith("--")), param.opts[0])
    given = _raw_values(args, option, 1)
    expected = next((v for k, v in _EXPECTED.items() if k in exc.message), None)
    what = f"expected {expected}" if expected else _lower_first(exc.message.rstrip("."))
    return f"{option}: {what}" + (f", got {given[0]!r}" if given else "")


def _is_number(word: str) -> bool:
    try:
        float(word)
    except ValueError:
        return False
    return True


def usage_error_line(exc: Any, args: Sequence[str] = ()) -> str:
    """One line for a click error `exc` raised while parsing `args` (the words after `zedo`)."""
    ctx = getattr(exc, "ctx", None)
    kind = type(exc).__name__
    hint = _help_hint(ctx)
    message = _lower_first(exc.format_message().rstrip("."))
    if kind == "NoSuchOption" and ctx is not None:
        message = f"no such option {exc.option_name}"
        close = difflib.get_close_matches(exc.option_name, _option_names(ctx), n=1, cutoff=0.6)
        if close:
            hint = f"did you mean {close[0]}? ({hint})"
    elif kind == "UsageError" and message.startswith("no such command"):
        name, _, suggestion = message.lower().partition(". did you mean ")
        message = name.replace("'", "")
        if suggestion:
            hint = f"did you mean {suggestion.rstrip('?').replace(chr(39), '')}? ({hint})"
    elif kind == "MissingParameter" and ctx is not None:
        param = getattr(exc, "param", None)
        name = getattr(param, "name", None) or ""
        shown = (getattr(param, "metavar", None) or name).upper()
        message = f"missing {shown}" if getattr(param, "param_type_name", "") == "argument" else message
        hint = ARGUMENT_HINTS.get((ctx.info_name, name), hint)
    elif kind == "BadParameter":
        bad = _bad_value(exc, args)
        message, hint = bad if bad is not None else (_invalid_value(exc, args) or message, hint)
    elif "requires" in message and "argument" in message:  # an option given without its value(s)
        message = message.replace("'", "").replace("requires an argument", "needs a value")
        message = message.replace("requires 2 arguments", "needs two values")
    message = re.sub(r"'(--?[\w-]+)'", r"\1", message)  # option names as typed, without quotes
    return " ".join(f"zedo: error: {message}; {hint}".split())  # one line, whatever the message held
