"""Shared pieces of the command-line front end: console, argument parsing, errors, output.

Every command module (``core``, ``ik``, ``viz``, ``symbolic``, ...) uses these so that all
commands parse joint values, report mistakes and print JSON the same way, and declare their
shared options (``--json``, ``--deg``, ``--lang`` ...) once, as ``Annotated`` types
(:data:`JsonOut`, :data:`Deg`, :data:`Lang`, ...; docs/adding-a-command.md). Nothing here
imports more than NumPy, Typer and Rich, so ``armkit --help`` stays fast.
"""

from __future__ import annotations

import json
import math
import os
import re
import sys
from pathlib import Path
from typing import Annotated, Any, List, NoReturn, Optional, Sequence

import numpy as np
import typer
from rich.console import Console
from rich.table import Table
from rich.text import Text

from .._io import OS_REASONS, check_writable
from .._text import esc, name_list, plain, shorten
from ..errors import JointLimitError
from ..locale import LANG, LANGUAGES, N_, _, choices, current_language  # noqa: F401  (re-exported for the commands)
from ..model import Robot, load

class SafeConsole(Console):
    """A Rich console that never sends a control character of a string to the terminal.

    Every string printed (messages, table cells, titles) has its control characters
    (ANSI escape sequences, bell, carriage return, bidi overrides) shown as ``\\xNN``
    before Rich reads it; user text inside armkit's markup must still go through
    :func:`esc` so that its brackets print literally.
    """

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        if kwargs.get("width") is None:   # Rich fixes COLUMNS at creation; read it (and the terminal) at each print
            self._width = None

    def render_str(self, text: str, **kwargs: Any) -> Text:  # type: ignore[override]
        return super().render_str(plain(text), **kwargs)


console = SafeConsole(highlight=False)
err_console = SafeConsole(stderr=True, highlight=False)

EXIT_OK, EXIT_FAILED, EXIT_BAD_INPUT = 0, 1, 2

# The user's language: --lang (taken by the command group for every command, kept in LANG), ARMKIT_LANG, the
# locale. _("...") translates a message from the gettext catalogue in armkit/locale (docs/languages.md); N_ marks
# one.


# Commands that take numbers as positional arguments let "-1" through as a value, not an option.
NUMERIC_ARGS = {"ignore_unknown_options": True, "allow_extra_args": False}


def os_reason(exc: OSError) -> str:
    """Why the system refused, in the current language for the errors armkit words itself
    (:data:`armkit._io.OS_REASONS`), in the system's own words for the others."""
    key = OS_REASONS.get(exc.errno or 0)
    return _(key) if key else (exc.strerror or type(exc).__name__)


def say(label: str, style: str, message: object, console_: Console | None = None) -> None:
    """Print ``label: message`` with only the label styled.

    The message is printed as plain text: never read as Rich markup (so ``[[joints]]`` and
    a robot named ``[/]`` print as they are), control characters shown as ``\\xNN``, cut
    after :data:`armkit._text.MAX_MESSAGE` characters. Every error and warning of the
    command line goes through here.
    """
    out = console_ or err_console
    out.print(Text.assemble((label, style), " ", shorten(plain(message))), soft_wrap=not wraps(out, columns=False))


def wraps(out: Console, columns: bool = True) -> bool:
    """Whether messages on ``out`` wrap between words at its width: on a terminal (Rich reads the width with
    ``os.get_terminal_size``; ``COLUMNS`` overrides it), and, with ``columns``, wherever ``COLUMNS`` is set (the
    width the output's lines are laid out for, as tables are: :func:`out_width`). Elsewhere (a pipe, a file) a
    message stays one line, so that grep finds it whole. Errors and warnings (:func:`say`) wrap on a terminal only:
    a program that reads them from a pipe gets one line each, whatever ``COLUMNS`` a test runner exported."""
    return out.is_terminal or (columns and os.environ.get("COLUMNS", "").isdigit())


def message(text: str | Text, console_: Console | None = None) -> None:
    """Print a message line (armkit's markup allowed in a ``str``) wrapped between words at the terminal's width
    (:func:`wraps`); never cut."""
    out = console_ or console
    out.print(text, soft_wrap=not wraps(out))


def fail(message: str | BaseException, code: int = EXIT_BAD_INPUT) -> NoReturn:
    """Print ``message`` to stderr and exit with ``code`` (never a traceback); a message of the library (an
    error's text) is shown in the user's language (:func:`armkit.locale.library.localize`): an error that carries
    its template and fields (given itself, or ``str(exc)`` of the error being handled) from the catalogue."""
    import sys

    from ..locale.library import localize

    handled = sys.exc_info()[1]
    if isinstance(message, str) and handled is not None and str(handled) == message:
        message = handled          # ``fail(str(exc))`` inside ``except``: the error itself, with its fields
    say(_("error:"), "bold red", localize(message, current_language()))
    raise SystemExit(code)


def warn(message: str) -> None:
    """Print ``warning: message`` to stderr (plain text, see :func:`say`)."""
    say(_("warning:"), "yellow", message)


def output_path(path: str | Path, suffixes: Sequence[str], what: str = "--output") -> Path:
    """Check an output file before any work: a wrong suffix or an unwritable place exits 2.

    The message is ``cannot write PATH: reason``; see :func:`armkit._io.check_writable`.
    """
    return check_writable(path, suffixes, what)


CHAIN: dict[str, Any] = {"base": None, "tip": None, "allow_outside": None}
"""``--base``/``--tip`` from the command line (taken by the command group, for every command)."""

ROBOT_HELP = ("Bundled robot name (see `armkit robots`) or path of a .toml or .urdf robot file; "
              "for a URDF, --base LINK and --tip LINK choose the chain, and --allow-outside reads mesh files outside "
              "its folder and package.")


# ---------------------------------------------------------------- options shared by the commands
# Each option that several commands take is declared once here, as an ``Annotated`` type; a command writes
# ``json_out: JsonOut = False`` and gets the same flag, the same help and the same parsing as every other
# (docs/adding-a-command.md). The default stays in the command's signature.

RobotArg = Annotated[str, typer.Argument(help=ROBOT_HELP)]
"""The robot (a bundled name or a robot file): the first argument of most commands."""

JointValues = Annotated[List[str], typer.Argument(help="Joint values, one per joint (rad, or deg with --deg).",
                                                  metavar="Q...")]
"""The joint values ``Q...`` (words, read by :func:`parse_q`)."""

JsonOut = Annotated[bool, typer.Option("--json", help="Print the answer as JSON (strict JSON on stdout).")]
"""``--json``: the command's answer as JSON (:func:`print_json`)."""

Deg = Annotated[bool, typer.Option("--deg", help="Angles on the command line are in degrees (else radians).")]
"""``--deg``: the command line's angles in degrees (prismatic joints stay lengths)."""

Strict = Annotated[bool, typer.Option("--strict", help="A joint outside its limits is an error.")]
"""``--strict``: a joint beyond its limits exits 2 instead of a warning."""

NoScene = Annotated[bool, typer.Option("--no-scene", help="No collision check.")]
"""``--no-scene``: check no collisions (each command says in its ``--scene`` help what a collision does there)."""

Seed = Annotated[int, typer.Option("--seed", help="Seed of the random numbers (the same seed, the same answer).")]
"""``--seed``: the command's random numbers (a sampled workspace, a random path, a map)."""

Picture = Annotated[str, typer.Option("-o", "--output", help="Picture file (.png, .pdf, .svg).")]
"""``-o/--output`` of a command that draws one picture."""

Lang = Annotated[Optional[str], typer.Option(
    "--lang", help=f"Language of the messages and labels: {choices(' or ')} (default: ARMKIT_LANG, else the "
                   "locale).")]
"""``--lang`` of a command that keeps it (the shell, the view, reach); :func:`check_lang` checks its value. Every
other command gets ``--lang`` from the command group, anywhere on the line."""


def check_lang(value: str | None) -> str | None:
    """A ``--lang`` value as a code of the language table (any case: ``KO`` is ``ko``), ``None`` when not given;
    any other value exits 2 with the list of languages."""
    if value is None:
        return None
    code = value.lower()
    if code not in LANGUAGES:
        fail(_("--lang must be one of {languages}, got {value!r}", languages=choices(), value=value))
    return code


def get_robot(name: str) -> Robot:
    """Load a bundled robot or a robot file (``--base/--tip`` choose a URDF chain); errors raise ArmkitError (exit 2)."""
    return load(name, base=CHAIN["base"], tip=CHAIN["tip"], allow_outside=bool(CHAIN.get("allow_outside")))


def scene_option(robot: Robot, scene_file: str | None, no_scene: bool) -> Any:
    """The scene a command checks collisions against, from ``--scene FILE`` / ``--no-scene``.

    The one rule of :func:`armkit.collision.resolve_scene`: by default the robot's own
    surroundings when its file has any (the fighter's torso and ground), else none; ``--scene``
    replaces the ground (the body stays); ``--no-scene`` none. Returns a Scene, or None for no
    check (pass it on as ``scene=scene_off(scene)``). A bad scene file raises ArmkitError (exit 2
    with ``file:line: field``).
    """
    if scene_file is not None and no_scene:
        fail("give --scene FILE or --no-scene, not both")
    if scene_file is None and not no_scene and getattr(robot, "collision", None) is None:
        return None
    from ..collision import resolve_scene

    return resolve_scene(robot, False if no_scene else scene_file)


def scene_off(scene: Any) -> Any:
    """A :func:`scene_option` answer as the library's ``scene=``: ``False`` (no check) for None."""
    return False if scene is None else scene


def checked_line(robot: Robot, scene: Any) -> str:
    """"checked against: ground, torso" (or "not checked for collisions"), in the user's language."""
    from ..collision import checked_against

    names = checked_against(robot, scene)
    shown = ", ".join(_(n) if n in _CHECKED_WORDS else n for n in names)   # a body's own name is the file's text
    return _("checked against: {names}", names=shown) if names else _("not checked for collisions")


_CHECKED_WORDS = (N_("ground"), N_("torso"), N_("itself"))
"""The names ``checked_against`` gives that are words (the ground plane, the default body, self-collision)."""


def parse_numbers(values: Sequence[str], what: str) -> np.ndarray:
    """Turn command-line words into finite floats, or fail with a one-line message."""
    out = []
    for v in values:
        try:
            x = float(v)
        except ValueError:
            fail(_("{what}: {value!r} is not a number", what=_(what), value=v))
        if not math.isfinite(x):
            fail(_("{what}: {value!r} is not a finite number", what=_(what), value=v))
        out.append(x)
    return np.array(out, dtype=float)


VECTOR_SPLIT = re.compile(r"[\s,]+")
"""What separates the numbers of a vector: commas, spaces or both (``180,0,0``, ``"180 0 0"``, ``180, 0, 0``)."""

VECTOR_OPTIONS: dict[str, int] = {"--rpy": 3, "--quat": 4, "--direction": 3, "--all-branches": 3, "--box": 6,
                                  "--xyz": 3}
"""Options whose value is a vector, and at most how many numbers it has: each takes ``--rpy 180 0 0`` as well as
``--rpy 180,0,0`` (:func:`join_vector_words` turns the first into the second before the command sees it)."""


def _is_number(word: str) -> bool:
    try:
        float(word)
    except ValueError:
        return False
    return True


def join_vector_words(args: Sequence[str]) -> list[str]:
    """The command line with every vector option's separate numbers joined by commas.

    ``--rpy 180 0 0`` becomes ``--rpy 180,0,0`` (up to :data:`VECTOR_OPTIONS` numbers are taken, only words that
    are numbers); ``--rpy 180,0,0``, ``--rpy=180,0,0`` and words after ``--`` are left as they are. The command
    then reads the value with :func:`parse_vector`, the one vector parser of the command line.

    >>> join_vector_words(["ik", "ur5", "0.4", "0.1", "0.3", "--rpy", "180", "0", "-90", "--deg"])
    ['ik', 'ur5', '0.4', '0.1', '0.3', '--rpy', '180,0,-90', '--deg']
    >>> join_vector_words(["plot", "fighter", "--all-branches", "100,50,80"])
    ['plot', 'fighter', '--all-branches', '100,50,80']
    """
    out: list[str] = []
    i = 0
    while i < len(args):
        word = args[i]
        out.append(word)
        i += 1
        if word == "--":
            out.extend(args[i:])
            break
        most = VECTOR_OPTIONS.get(word)
        if most is None or i >= len(args) or "," in args[i]:
            continue
        taken: list[str] = []
        while i < len(args) and len(taken) < most and _is_number(args[i]):
            taken.append(args[i])
            i += 1
        out.append(",".join(taken) if taken else args[i])
        if not taken:
            i += 1
    return out


def parse_vector(text: str, sizes: int | Sequence[int], what: str, names: str = "") -> np.ndarray:
    """A vector option's value (``180,0,0``, ``"180 0 0"``, ``180, 0, 0``) as finite floats, or exit 2.

    ``sizes``: the count, or the counts, allowed; ``names`` says what the numbers are (``"roll pitch yaw"``) in the
    message of a wrong count. Every vector of the command line goes through here (and the shell's through
    :data:`VECTOR_SPLIT`).

    >>> parse_vector("180,0,0", 3, "--rpy").tolist(), parse_vector("1.2 0.3", (2, 3), "--all-branches").tolist()
    ([180.0, 0.0, 0.0], [1.2, 0.3])
    """
    allowed = (sizes,) if isinstance(sizes, int) else tuple(sizes)
    v = parse_numbers([w for w in VECTOR_SPLIT.split(text.strip()) if w], what)
    if len(v) not in allowed:
        counts = _(" or ").join(str(k) for k in allowed)
        fail(_("{what} needs {counts} numbers{names}, separated by commas or spaces; got {k}",
               what=what, counts=counts, names=f" ({names})" if names else "", k=len(v)))
    return v


def parse_q(robot: Robot, values: Sequence[str], deg: bool, strict: bool = False) -> np.ndarray:
    """Joint values from the command line, in radians/length units, checked against the limits.

    ``deg`` converts revolute joints only (prismatic joints are always lengths).
    Outside a limit: a warning, or exit 2 with ``strict``.
    """
    q = parse_numbers(values, N_("joint values"))
    if q.shape != (robot.n,):
        fail(_("robot {robot!r} has {n} joints ({names}); got {k} value(s)", robot=robot.name, n=robot.n,
               names=name_list(robot.joint_names), k=len(q)))
    typed = q
    if deg:
        q = np.where(robot.prismatic, q, np.radians(q))
    bad = _limit_violations(robot, q)
    hint = "" if deg else _deg_hint(robot, typed)
    if bad:
        msg = _("joint limit: {detail}", detail=name_list(bad, limit=6, sep="; "))
        if strict:
            raise JointLimitError(msg + hint)
        warn(_("{message} (computing anyway; --strict makes this an error)", message=msg) + hint)
    elif hint:
        warn(_("joint values in radians") + hint)
    return q


def _limit_violations(robot: Robot, q: np.ndarray) -> list[str]:
    """:meth:`Robot.limit_violations` in the user's language."""
    if not robot.limit_violations(q):
        return []
    out = []
    for j, v in zip(robot.joints, q):
        if v < j.lower - 1e-12 or v > j.upper + 1e-12:
            if j.is_prismatic:
                out.append(_("{joint} = {value} {unit} outside [{lower}, {upper}] {unit}", joint=j.name,
                             value=f"{v:g}", lower=f"{j.lower:g}", upper=f"{j.upper:g}", unit=robot.unit))
            else:
                out.append(_("{joint} = {value} {unit} outside [{lower}, {upper}] {unit}", joint=j.name,
                             value=f"{math.degrees(v):.3f}", lower=f"{math.degrees(j.lower):.3f}",
                             upper=f"{math.degrees(j.upper):.3f}", unit="deg"))
    return out


def _deg_hint(robot: Robot, typed: np.ndarray) -> str:
    """``"; did you mean --deg? ..."`` when radian values look like degrees, else ``""``.

    They look like degrees when every non-zero revolute value is beyond a full turn (|q| > 2 pi), or
    when the values break a joint limit in radians but are inside every limit read as degrees.
    """
    rev = ~np.asarray(robot.prismatic, dtype=bool)
    values = typed[rev]
    if not rev.any() or not np.any(values):
        return ""
    as_deg = np.where(robot.prismatic, typed, np.radians(typed))
    beyond_turn = bool(np.all(np.abs(values[values != 0]) > 2 * math.pi))
    fits_as_deg = bool(robot.limit_violations(typed)) and not robot.limit_violations(as_deg)
    if not (beyond_turn or fits_as_deg):
        return ""
    if fits_as_deg:
        shown = " ".join(f"{v:g}" for v in typed)
        return _("; did you mean --deg? ({values} read as degrees are inside the limits)", values=shown)
    return _("; did you mean --deg? (every angle is beyond a full turn, 2 pi rad)")


def q_display(robot: Robot, q: np.ndarray, deg: bool = True) -> list[str]:
    """Joint values as text with units: degrees for revolute joints, length units for prismatic."""
    return [f"{v:.6g} {robot.unit}" if p else (f"{math.degrees(v):.4f}°" if deg else f"{v:.6f} rad")
            for v, p in zip(q, robot.prismatic)]


def out_width() -> int:
    """Columns to print tables in: the terminal's, or COLUMNS when set; else at least 150 for pipes and files
    (nothing cut)."""
    import os

    if console.is_terminal or os.environ.get("COLUMNS", "").isdigit():
        return console.width
    return max(console.width, 150)


def natural_width(table: Table) -> int:
    """Columns a table needs with nothing cut or wrapped, without its title: Rich's own measure of the table on a
    wide console (the width it renders at there, without rendering it: 2 ms less a table)."""
    import copy
    import io

    from rich.measure import Measurement

    bare = copy.copy(table)
    bare.title = bare.caption = None
    wide = Console(file=io.StringIO(), width=1000, no_color=True, highlight=False)
    return Measurement.get(wide, wide.options, bare).maximum


def print_fitted(*tables: Table) -> None:
    """Print the first table that fits :func:`out_width`; when none does, the last one as one record per row
    (:func:`table_records`), so that no number is cut or broken across lines."""
    width = out_width()
    out = console if width == console.width else SafeConsole(highlight=False, width=width)
    for t in tables:
        if natural_width(t) <= width:
            out.print(t)
            return
    title, records = table_records(tables[-1])
    print_records(title, records, width)


def print_table(table: Table) -> None:
    """Print a table as it is when it fits :func:`out_width`, else one record per row."""
    print_fitted(table)


def _cell_text(cell: Any) -> str:
    return cell.plain if isinstance(cell, Text) else Text.from_markup(str(cell)).plain


def table_records(table: Table) -> tuple[str, list[tuple[str, list[str]]]]:
    """A Rich table as ``(title, [(head, ["header value", ...]), ...])`` for :func:`print_records`: the first
    cell of a row is its head, each other non-empty cell an item led by its column header."""
    title = _cell_text(table.title) if table.title is not None else ""
    headers = [" ".join(_cell_text(c.header).split()) for c in table.columns]
    cells = [[_cell_text(v) for v in c.cells] for c in table.columns]
    records = []
    for i in range(table.row_count):
        row = [" ".join(col[i].split()) if i < len(col) else "" for col in cells]
        head = f"{headers[0]} {row[0]}".strip() if headers[0] and row[0] and not row[0][:1].isalpha() else row[0]
        items = [f"{h}: {v}" if h else v for h, v in zip(headers[1:], row[1:]) if v]
        records.append((head, items))
    return title, records


def print_records(title: str, records: Sequence[tuple[str, Sequence[str]]], width: int | None = None) -> None:
    """A table too wide for the terminal, one record per row: a bold head line, then its ``name value`` items
    wrapped between items (never inside a number). All text is printed plain (never read as markup)."""
    width = width or out_width()
    out = console if width == console.width else SafeConsole(highlight=False, width=width)
    out.print(Text(title, style="bold"))
    for head, items in records:
        out.print(Text(head, style="bold"), soft_wrap=True)
        line = "  "
        for item in items:
            pieces = _split_long(item, width - 4)
            if line.strip() and (len(pieces) > 1 or len(line) + len(item) > width):
                out.print(Text(line.rstrip()), soft_wrap=True)
                line = "  "
            for piece in pieces[:-1]:       # an item too long for one line: its own lines, broken at spaces
                out.print(Text("  " + piece), soft_wrap=True)
            line += pieces[-1] + "  "
            if len(pieces) > 1:
                out.print(Text(line.rstrip()), soft_wrap=True)
                line = "  "
        if line.strip():
            out.print(Text(line.rstrip()), soft_wrap=True)


def _split_long(item: str, room: int) -> list[str]:
    """An item longer than ``room`` broken at its spaces (a number never holds one)."""
    import textwrap

    if len(item) <= room:
        return [item]
    return textwrap.wrap(item, max(room, 20), break_long_words=False, break_on_hyphens=False) or [item]


NOISE = 1e-9
"""A table number smaller than this (in its printed unit: deg, m, mm) is rounding noise and printed as 0."""


def fixed(value: float, digits: int = 3, sign: str = "") -> str:
    """``value`` with ``digits`` decimals, never ``-0.000``: a value that rounds to zero prints without a sign.

    ``sign=" "`` leaves a space where the minus would be (columns of a matrix line up).

    >>> fixed(-0.0004), fixed(-1e-17, 6, " "), fixed(-2.5), fixed(float("nan"))
    ('0.000', ' 0.000000', '-2.500', 'nan')
    """
    text = f"{value:{sign}.{digits}f}"
    if text.lstrip().startswith("-") and float(text) == 0.0:
        text = text.replace("-", " " if sign == " " else "", 1)
    return text


def sig(value: float, digits: int = 6) -> str:
    """``value`` to ``digits`` significant digits, rounding noise (below :data:`NOISE`) shown as 0.

    >>> sig(1.24991e-17), sig(-1e-12), sig(0.1), sig(-2.5e-3)
    ('0', '0', '0.1', '-0.0025')
    """
    return f"{(0.0 if abs(value) < NOISE else value) + 0.0:.{digits}g}"


def count(n: int) -> str:
    """A count with thousands separators: ``count(1000000)`` is ``'1,000,000'``."""
    return f"{int(n):,}"


def pose_table(T: np.ndarray, unit: str, title: str = "pose", full: bool = False) -> Table:
    """A 4x4 pose as a Rich table with the translation column labelled with its unit (no ``-0.000000``);
    ``full``: with the bottom row ``0 0 0 1`` (the whole homogeneous matrix, as a homework writes it)."""
    t = Table(title=title, show_header=True, header_style="bold")
    for h in ("", "x", "y", "z", f"p ({unit})"):
        t.add_column(h, justify="right")
    for i, row in enumerate(T[:3]):
        t.add_row("xyz"[i], *(fixed(v, 6, " ") for v in row[:3]), fixed(row[3], 6, " "))
    if full:
        t.add_row("", *(fixed(v, 0, " ") for v in T[3]))
    return t


def print_json(data: Any) -> None:
    """Print data as strict JSON on stdout (NumPy arrays become lists, NaN and infinities null)."""
    def clean(o: Any) -> Any:   # strict JSON: NaN and infinities become null
        if isinstance(o, np.ndarray):
            o = o.tolist()
        elif isinstance(o, (np.floating, np.integer, np.bool_)):
            o = o.item()
        if isinstance(o, float):
            return o if math.isfinite(o) else None
        if isinstance(o, dict):
            return {k: clean(v) for k, v in o.items()}
        if isinstance(o, (list, tuple)):
            return [clean(v) for v in o]
        return o

    sys.stdout.write(json.dumps(clean(data), indent=2, ensure_ascii=False, allow_nan=False) + "\n")
