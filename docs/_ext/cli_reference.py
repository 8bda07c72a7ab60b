"""Write the command-line reference from ik7r's own argument parser at build time.

``docs/_generated/cli-reference.md`` is regenerated on every build from the parser that
``ik7r`` runs (``build_parser()`` of :mod:`ik7r.cli`), so the page cannot drift from the
program: every command, its usage line, its description and every option with its help.
``docs/cli.md`` includes it.
"""

from __future__ import annotations

import argparse
import importlib
from pathlib import Path


def find_build_parser():
    """``build_parser`` of the command line, wherever :mod:`ik7r.cli` keeps it."""
    cli = importlib.import_module("ik7r.cli")
    build = getattr(cli, "build_parser", None)
    if build is None:  # a package whose __init__ does not re-export it
        for name in ("main", "app"):
            try:
                module = importlib.import_module(f"ik7r.cli.{name}")
            except ImportError:
                continue
            build = getattr(module, "build_parser", None)
            if build is not None:
                break
    if build is None:
        raise RuntimeError("ik7r.cli has no build_parser()")
    return build


def _subparsers(parser: argparse.ArgumentParser):
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            helps = {a.dest: a.help for a in action._choices_actions}
            for name, sub in action.choices.items():
                yield name, sub, helps.get(name)


def _escape(text: str) -> str:
    return text.replace("|", "\\|").replace("*", "\\*").replace("<", "&lt;")


def _options_table(parser: argparse.ArgumentParser) -> list[str]:
    rows = []
    for action in parser._actions:
        if isinstance(action, (argparse._HelpAction, argparse._SubParsersAction)):
            continue
        if action.help == argparse.SUPPRESS:
            continue
        if action.option_strings:
            metavar = ""
            if action.nargs != 0:
                mv = action.metavar or action.dest.upper()
                metavar = " " + (" ".join(mv) if isinstance(mv, tuple) else str(mv))
            name = ", ".join(f"{o}{metavar}" for o in action.option_strings)
        else:
            mv = action.metavar or action.dest
            name = " ".join(mv) if isinstance(mv, tuple) else str(mv)
        text = action.help or ""
        if "%(default)" in text:
            text = text % {"default": action.default}
        elif action.default not in (None, False, argparse.SUPPRESS) and action.option_strings \
                and action.nargs != 0 and "default" not in text:
            text = f"{text} (default: {action.default})" if text else f"default: {action.default}"
        if action.choices and not isinstance(action, argparse._SubParsersAction):
            text += f" (one of: {', '.join(map(str, action.choices))})"
        rows.append(f"| `{_escape(name)}` | {_escape(' '.join(text.split()))} |")
    if not rows:
        return []
    return ["| argument | meaning |", "|---|---|", *rows, ""]


def _section(parser: argparse.ArgumentParser, title: str, level: int, help_line: str | None,
             out: list[str]) -> None:
    out.append(f"{'#' * level} `{title}`")
    out.append("")
    if help_line:
        out.append(_escape(help_line[0].upper() + help_line[1:]) + ".")
        out.append("")
    usage = " ".join(parser.format_usage().split())
    out += ["```text", usage.removeprefix("usage: "), "```", ""]
    if parser.description:
        out += [_escape(" ".join(parser.description.split())), ""]
    out += _options_table(parser)
    for name, sub, sub_help in _subparsers(parser):
        _section(sub, f"{title} {name}", min(level + 1, 6), sub_help, out)


def markdown(parser: argparse.ArgumentParser | None = None) -> str:
    """The reference page (Markdown) of ``parser`` (default: ik7r's)."""
    parser = parser or find_build_parser()()
    out = ["<!-- generated from ik7r's argument parser by docs/_ext/cli_reference.py; do not edit -->",
           ""]
    out += ["## Global options", "", "```text", " ".join(parser.format_usage().split())
            .removeprefix("usage: "), "```", ""]
    out += _options_table(parser)
    for name, sub, sub_help in _subparsers(parser):
        _section(sub, f"ik7r {name}", 2, sub_help, out)
    return "\n".join(out).rstrip() + "\n"


def write(app) -> None:
    target = Path(app.srcdir) / "_generated" / "cli-reference.md"
    target.parent.mkdir(exist_ok=True)
    text = markdown()
    if not target.exists() or target.read_text() != text:  # untouched: no rebuild
        target.write_text(text)


def setup(app):
    app.connect("builder-inited", write)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
