"""The ``armkit`` command: a thin Typer + Rich front end over the public functions.

Errors: ``_ArmkitGroup`` turns any ArmkitError into a one-line message with exit 2.
Each module registers its commands (``core``: robots, info, fk, jacobian; ``ik``; ``viz``;
``symbolic``). Heavy imports live inside the command bodies so that ``armkit --help``
starts fast, and the CLI uses the NumPy kernels (no JIT start-up cost).

Exit codes: 0 success, 1 a computation that failed (e.g. unreachable target), 2 bad input.
"""

from __future__ import annotations

import functools
import importlib
import os
from typing import Optional

import typer
from typer.core import TyperGroup
from .. import __version__, _jit_loader, kinematics
from ..errors import ArmkitError, WriteInterrupted

__all__ = ["app", "main"]


class _ArmkitGroup(TyperGroup):
    """Turns every armkit error (a user mistake: bad file, bad shape, unknown robot) into one line, exit 2.

    Also: an unwritable output (``cannot write PATH: reason``) exit 2; Ctrl-C exit 130
    (``interrupted; PATH not written`` when a file was being written, the old file intact);
    input too deep or too large for Python (RecursionError, OverflowError, MemoryError)
    exit 2 with a message instead of a traceback.
    """

    def __init__(self, *args, **kwargs):  # type: ignore[no-untyped-def]
        super().__init__(*args, **kwargs)
        _tidy_help(self)

    def parse_args(self, ctx, args):  # type: ignore[no-untyped-def]
        """Take ``--base LINK`` / ``--tip LINK`` (the chain of a URDF, see ``common.get_robot``), ``--allow-outside``
        (a URDF's mesh files may lie anywhere) and ``--lang``
        from anywhere on the line; commands (and subcommands) with their own ``--lang`` still get it."""
        from . import common

        common.CHAIN.update(base=None, tip=None, allow_outside=None)
        common.LANG.update(lang=None)
        args = common.join_vector_words(args)    # --rpy 180 0 0 == --rpy 180,0,0 on every command
        words = [a for k, a in enumerate(args)
                 if not a.startswith("-") and (k == 0 or args[k - 1] not in ("--base", "--tip", "--lang"))]
        command = self.commands.get(words[0]) if words else None
        if command is not None and hasattr(command, "commands") and len(words) > 1:   # a group: `reach build`
            command = command.commands.get(words[1], command)  # type: ignore[attr-defined]
        own_lang = command is not None and any("--lang" in getattr(p, "opts", ()) for p in command.params)
        rest, lang_words, i = [], [], 0
        while i < len(args):
            word = args[i]
            if word == "--allow-outside" and "--" not in args[:i]:   # URDF meshes from anywhere (issue 24)
                common.CHAIN["allow_outside"] = True
                i += 1
                continue
            key = next((k for k in ("--base", "--tip", "--lang") if word == k or word.startswith(k + "=")), None)
            if key is None or "--" in args[:i]:
                rest.append(word)
                i += 1
                continue
            if "=" in word:
                value, i = word.split("=", 1)[1], i + 1
            elif i + 1 < len(args):
                value, i = args[i + 1], i + 2
            elif key == "--lang":
                common.fail(common._("--lang needs a language: {languages}", languages=common.choices()))
            else:
                common.fail(common._("{key} needs a link name (e.g. {key} tool0)", key=key))
            if key == "--lang":
                common.LANG["lang"] = common.check_lang(value)
                lang_words = ["--lang", value]
                continue
            common.CHAIN[key[2:]] = value
        if own_lang and lang_words and "--" not in rest:   # commands with their own --lang (shell, view ...)
            rest += lang_words
        return super().parse_args(ctx, rest)

    def invoke(self, ctx):  # type: ignore[no-untyped-def]
        import warnings


        def show(message, category, filename, lineno, file=None, line=None):  # type: ignore[no-untyped-def]
            from ..locale import current_language
            from ..locale.library import localize
            from .common import warn

            warn(localize(message, current_language()))   # one line, never a source line or a class name

        shown = warnings.showwarning
        warnings.showwarning = show
        _word_the_notes()
        try:
            return super().invoke(ctx)
        except ArmkitError as exc:
            from ..locale import current_language
            from ..locale.library import localize
            from .common import EXIT_BAD_INPUT, _, say

            say(_("error:"), "bold red", localize(exc, current_language()))
            raise SystemExit(EXIT_BAD_INPUT) from None
        except WriteInterrupted as exc:
            from .common import _, say

            say(_("interrupted;"), "bold red", _("{path} not written", path=exc.path))
            raise SystemExit(130) from None
        except KeyboardInterrupt:
            from .common import _, say

            say(_("interrupted"), "bold red", "")
            raise SystemExit(130) from None

        except RecursionError:
            from .common import EXIT_BAD_INPUT, _, say

            say(_("error:"), "bold red", _("the input is nested too deeply to process"))
            raise SystemExit(EXIT_BAD_INPUT) from None
        except (OverflowError, MemoryError) as exc:
            from .common import EXIT_BAD_INPUT, _, say

            what = _("a number is too large") if isinstance(exc, OverflowError) else _("not enough memory")
            say(_("error:"), "bold red", f"{what} ({type(exc).__name__}: {exc})")
            raise SystemExit(EXIT_BAD_INPUT) from None
        except OSError as exc:
            # a path the system refuses that no command's own check caught (a name too long, a device error): the
            # user's input, said in one line, exit 2; a closed output pipe is not an error
            if isinstance(exc, BrokenPipeError):
                raise
            from .common import EXIT_BAD_INPUT, _, os_reason, say

            reason = os_reason(exc)
            message = (_("the operating system refused: {reason}", reason=reason) if exc.filename is None else
                       _("cannot use {path!r}: {reason}", path=os.fsdecode(exc.filename), reason=reason))
            say(_("error:"), "bold red", message)
            raise SystemExit(EXIT_BAD_INPUT) from None
        finally:
            # what parse_args set for this command ends with it: in a process that goes on (a program or a test
            # calling the app, the shell), the library's messages and pictures made afterwards were in the last
            # command's --lang, and its warnings went through the command line's printer
            from . import common

            common.LANG.update(lang=None)
            common.CHAIN.update(base=None, tip=None, allow_outside=None)
            warnings.showwarning = shown


_TYPE_LABELS = {"float": "FLOAT", "int": "INT", "str": "TEXT", "path": "PATH", "list[str]": "TEXT"}


def _type_label(param, ctx):  # type: ignore[no-untyped-def]
    """What ``--help`` shows after an option: nothing for a flag, the option's metavar, or ``FLOAT``, ``INT``,
    ``TEXT`` (``FLOAT FLOAT FLOAT`` for three numbers), never Typer's ``<bool>`` or ``<list[str]>``."""
    if getattr(param, "is_flag", False) or getattr(param, "count", False):
        return None
    if param.metavar is not None:
        return param.metavar
    shown = type(param).display_type(param, ctx).strip("<>").removesuffix("...").strip("<>")
    words = [_TYPE_LABELS.get(w, w.upper()) for w in shown.split(",")]
    return " ".join(words) + ("..." if param.nargs == -1 or getattr(param, "multiple", False) else "")


def _chain(base: Optional[str] = typer.Option(None, "--base", metavar="LINK",
                                              help="URDF: the link where the chain starts (default: the root link)."),
           tip: Optional[str] = typer.Option(None, "--tip", metavar="LINK",
                                             help="URDF: the link where the chain ends, e.g. tool0 (default: the "
                                                  "single leaf reached through moving joints)."),
           allow_outside: bool = typer.Option(False, "--allow-outside",
                                              help="URDF: read mesh files outside its folder and package.")
           ) -> None:  # pragma: no cover  (never called: only its options are used, by _chain_options)
    """The options the command group takes from anywhere on the line, declared once for ``--help``."""


@functools.lru_cache(maxsize=1)
def _chain_options() -> tuple:  # type: ignore[type-arg]
    """``--base``, ``--tip``, ``--allow-outside`` as help entries: the command group takes them from anywhere on
    the line (``_ArmkitGroup.parse_args``), so the commands never receive them (``expose_value=False``)."""
    import types

    from typer.main import get_command

    helper = typer.Typer(add_completion=False)
    helper.command()(_chain)
    params = tuple(get_command(helper).params)
    for param in params:
        param.expose_value = False
        param.display_type_rich = types.MethodType(_type_label, param)  # type: ignore[attr-defined]
    return params


def _tidy_help(command) -> None:  # type: ignore[no-untyped-def]
    """Every command's ``--help``: plain type labels (:func:`_type_label`), no label on arguments (their name says
    what they are), and ``--base/--tip/--allow-outside`` listed on every command that takes a robot."""
    import types

    for param in command.params:
        if hasattr(param, "display_type_rich"):
            if getattr(param, "param_type_name", "") == "argument":
                param.display_type_rich = lambda ctx: None
            else:
                param.display_type_rich = types.MethodType(_type_label, param)
    get_help_option = command.get_help_option

    def help_option(ctx):  # type: ignore[no-untyped-def]
        option = get_help_option(ctx)
        if option is not None and hasattr(option, "display_type_rich"):
            option.display_type_rich = lambda ctx: None
        return option

    command.get_help_option = help_option
    if getattr(command, "help", None):
        command.help = reflow(command.help)
    names = {p.name for p in command.params}
    if "robot" in names and "base" not in names and "tip" not in names:
        command.params.extend(_chain_options())
    for sub in getattr(command, "commands", {}).values():
        _tidy_help(sub)


def reflow(text: str) -> str:
    r"""A docstring's paragraphs as single lines, so that ``--help`` wraps them at the terminal's width (no line
    broken where the source was); ``Example:`` lines stay lines of their own.

    >>> reflow("One sentence\nwrapped.\n\nExample: a\nExample: b")
    'One sentence wrapped.\n\nExample: a\nExample: b'
    """
    out = []
    for para in text.split("\n\n"):
        lines: list[str] = []
        for line in para.splitlines():
            if lines and not line.lstrip().startswith("Example") and not lines[-1].lstrip().startswith("Example"):
                lines[-1] += " " + line.strip()
            else:
                lines.append(line.strip())
        out.append("\n".join(lines))
    return "\n\n".join(out)


_COMMAND_MODULES = ("core", "ik", "viz", "symbolic", "view", "reach", "warmup", "so101")

app = typer.Typer(
    name="armkit",
    help="Serial robot-arm kinematics: DH models, FK, Jacobians, IK, plots.\n\n"
         "Example: armkit fk fighter 30 45 60 --deg",
    no_args_is_help=True,
    cls=_ArmkitGroup,
    add_completion=False,
    pretty_exceptions_enable=False,
    rich_markup_mode="rich",
)



def _print_version(value: bool) -> None:
    if value:
        typer.echo(f"armkit {__version__}")
        raise typer.Exit()


def _word_the_notes() -> None:
    """Have the back end's notes on stderr (compiling the kernels, the warm-up process) worded in the user's
    language, from the catalogue like every other text of the command line."""
    from .common import _

    _jit_loader.set_renderer(lambda template, fields: _(template, **fields))


@app.callback()
def _options(version: bool = typer.Option(False, "--version", callback=_print_version, is_eager=True,
                                          help="Print armkit's version and exit.")) -> None:
    pass


def _register_commands(group: typer.Typer, names: tuple[str, ...] = _COMMAND_MODULES) -> None:
    """Import each command module ``armkit.cli.<name>`` and let it add its commands to ``group``.

    A listed module that is missing is an error (a broken installation), never skipped:
    ``armkit`` without ``ik`` would only fail later, as "No such command".

    Raises
    ------
    ImportError
        Naming the missing module; other import errors propagate unchanged.
    """
    for name in names:
        module_name = f"armkit.cli.{name}"
        try:
            module = importlib.import_module(module_name)
        except ModuleNotFoundError as exc:
            if exc.name != module_name:      # the module exists; something it imports is missing
                raise
            raise ImportError(f"the command module {module_name} is missing: it is listed in "
                              f"armkit.cli._COMMAND_MODULES but not installed (reinstall armkit)",
                              name=module_name) from exc
        module.register(group)


_register_commands(app)


def main() -> None:
    """Entry point of the ``armkit`` command (NumPy kernels unless ARMKIT_BACKEND says otherwise)."""
    os.environ.setdefault("ARMKIT_BACKEND", "numpy")

    kinematics.set_backend(os.environ["ARMKIT_BACKEND"])  # type: ignore[arg-type]
    try:
        app(standalone_mode=True)
    except KeyboardInterrupt:
        raise SystemExit(130) from None
