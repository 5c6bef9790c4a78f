"""The ``armkit`` command: a thin Typer + Rich front end over the public functions.

Errors: ``_ArmkitGroup`` turns any ArmkitError into a one-line message with exit 2.
Each module registers its commands (``core``: robots, info, fk, jacobian; ``ik``; ``viz``;
``symbolic``). Heavy imports live inside the command bodies so that ``armkit --help``
starts fast, and the CLI uses the NumPy kernels (no JIT start-up cost).

Exit codes: 0 success, 1 a computation that failed (e.g. unreachable target), 2 bad input.
"""

from __future__ import annotations

import importlib
import os

import typer
from typer.core import TyperGroup

__all__ = ["app", "main"]


class _ArmkitGroup(TyperGroup):
    """Turns every armkit error (a user mistake: bad file, bad shape, unknown robot) into one line, exit 2.

    Also: an unwritable output (``cannot write PATH: reason``) exit 2; Ctrl-C exit 130
    (``interrupted; PATH not written`` when a file was being written, the old file intact);
    input too deep or too large for Python (RecursionError, OverflowError, MemoryError)
    exit 2 with a message instead of a traceback.
    """

    def parse_args(self, ctx, args):  # type: ignore[no-untyped-def]
        """Take ``--base LINK`` / ``--tip LINK`` (the chain of a URDF, see ``common.get_robot``), ``--allow-outside``
        (a URDF's mesh files may lie anywhere) and ``--lang``
        from anywhere on the line; commands (and subcommands) with their own ``--lang`` still get it."""
        from . import common

        common.CHAIN.update(base=None, tip=None, allow_outside=None)
        common.LANG.update(lang=None)
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
                common.fail(common._("--lang needs a language: en or ko"))
            else:
                common.fail(common._("{key} needs a link name (e.g. {key} tool0)", key=key))
            if key == "--lang":
                if value.lower() not in ("en", "ko"):
                    common.fail(common._("--lang must be en or ko, got {value!r}", value=value))
                common.LANG["lang"] = value.lower()
                lang_words = ["--lang", value]
                continue
            common.CHAIN[key[2:]] = value
        if own_lang and lang_words and "--" not in rest:   # commands with their own --lang (shell, view ...)
            rest += lang_words
        return super().parse_args(ctx, rest)

    def invoke(self, ctx):  # type: ignore[no-untyped-def]
        import warnings

        from ..errors import ArmkitError, WriteInterrupted

        def show(message, category, filename, lineno, file=None, line=None):  # type: ignore[no-untyped-def]
            from ..locale import current_language
            from ..locale.library import localize
            from .common import warn

            warn(localize(str(message), current_language()))   # one line, never a source line or a class name

        warnings.showwarning = show
        try:
            return super().invoke(ctx)
        except ArmkitError as exc:
            from ..locale import current_language
            from ..locale.library import localize
            from .common import EXIT_BAD_INPUT, _, say

            say(_("error:"), "bold red", localize(str(exc), current_language()))
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

for _name in _COMMAND_MODULES:
    try:
        _module = importlib.import_module(f"armkit.cli.{_name}")
    except ModuleNotFoundError as _exc:  # a command module not written yet
        if _exc.name != f"armkit.cli.{_name}":
            raise
        continue
    _module.register(app)


def main() -> None:
    """Entry point of the ``armkit`` command (NumPy kernels unless ARMKIT_BACKEND says otherwise)."""
    os.environ.setdefault("ARMKIT_BACKEND", "numpy")
    from .. import kinematics

    kinematics.set_backend(os.environ["ARMKIT_BACKEND"])  # type: ignore[arg-type]
    try:
        app(standalone_mode=True)
    except KeyboardInterrupt:
        raise SystemExit(130) from None
