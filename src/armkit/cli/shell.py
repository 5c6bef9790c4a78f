r"""The interactive shell (the typed loop of the club's fighting-robot report, done safely): ``armkit shell fighter``.

A line holds one or more statements separated by ``;``::

    theta1 = 30; theta2 = 45; theta3 = 60     joint by number (theta1, q1, j1) or by name (yaw = 30)
    q 30 45 60                                every joint at once
    goto 100 50 80  or  [100 50 80]  or  100 50 80    move the end point to a target (IK)
    theta2 = 90/2      theta1 = pi/4 rad      values may be simple arithmetic
    branch elbow-up    branch auto   branch   pick / list IK branches
    home   limits   units deg|rad   lang ko|en   show   help   exit | quit (or Ctrl-D)

The grammar is a handful of regular expressions over the words of a statement; numbers
are parsed with ``float`` after a strict pattern match, and values that are arithmetic
(numbers, ``pi``, ``+ - * /``, parentheses) by the small hand-written parser in
:mod:`armkit._arith`. Nothing typed is ever evaluated as code. A line that does not parse changes nothing and gets one line of explanation.
After each command that moves the arm, the shell prints the joint values, the end
point (and orientation) and the IK branch, and redraws the arm: in a window when there
is a display, else into ``out/shell/step_NNN.png``.

:class:`Shell` does the work and is driven line by line with :meth:`Shell.execute`
(tests feed it scripts); :meth:`Shell.run` is the read loop (prompt_toolkit with
history and tab completion on a terminal, plain lines from a pipe). This module holds the
grammar, the loop and the output; what each command does is in :mod:`armkit.cli.shell_commands`
(the base class :class:`~armkit.cli.shell_commands.ShellCommands`).

Examples
--------
>>> import armkit, io
>>> from rich.console import Console
>>> sh = Shell(armkit.load("fighter"), lang="en", plot="none", console=Console(file=io.StringIO()))
>>> sh.execute("theta1 = 30; theta2 = 45; theta3 = 60").status
'ok'
>>> [round(float(v), 3) for v in sh.end_point]
[24.861, 14.353, 187.181]
>>> sh.execute("print(__import__('os'))").status
'error'
>>> sh.execute("exit").status
'exit'
"""

from __future__ import annotations

import io
import math
import os
import re
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Iterable, Optional, TextIO

import numpy as np

from .._text import MAX_MESSAGE, esc, name_list, plain, shorten
from ..errors import ArgumentError, ParseError
from ..locale import LANGUAGES, default_language, message
from ..kinematics import fk
from ..model.robot import Robot
from ..spatial import rotation_to_rpy
from .common import VECTOR_SPLIT
from .shell_commands import ShellCommands, _clip

__all__ = ["Shell", "ShellOutput", "parse_numbers", "ParseError"]   # ParseError lives in armkit.errors

_NUMBER = r"[+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?"
_NUMBER_RE = re.compile(rf"^{_NUMBER}$")
# ``name = value [unit]``. The value is a greedy ``.*`` and its unit is split off in Python (_split_unit): the
# earlier lazy ``(\S.*?)\s*(unit)?$`` backtracked quadratically on ``theta1 = 1`` + 99,000 spaces + ``x``.
_ASSIGN_RE = re.compile(r"^([A-Za-z_][A-Za-z_0-9\-]*)\s*=\s*(\S.*)$",
                        re.IGNORECASE | re.DOTALL)   # the value: a number or simple arithmetic (armkit._arith)
_UNITS = ("radians", "degrees", "radian", "degree", "deg", "rad", "mm", "cm", "°", "m")   # longest first
_INDEXED_RE = re.compile(r"^(?:theta|q|j|joint)(\d+)$", re.IGNORECASE)
_WORD_RE = re.compile(r"^([A-Za-z?]+)(?:\s+(.*))?$", re.DOTALL)
_BRACKET_RE = re.compile(r"^[\[(](.*)[\])]$", re.DOTALL)
_SPLIT_RE = VECTOR_SPLIT      # 100 50 80, 100,50,80, [100, 50, 80]: the command line's vector rule (cli.common)
EXIT_WORDS = ("exit", "quit", "bye", ":q")
MAX_PICTURES = 500        # pictures one session writes before it stops drawing (a note says so)
MAX_LINE = 10_000         # characters of one input line; a longer line is refused unread (issue 24)


def _split_unit(value: str) -> tuple[str, Optional[str]]:
    """``"30 deg"`` -> ``("30", "deg")``: the longest unit word that ends ``value`` and leaves a value before it
    (case-insensitive), else ``(value, None)``. Linear in ``len(value)``."""
    value = value.rstrip()
    for unit in _UNITS:
        if len(value) > len(unit) and value[-len(unit):].lower() == unit:
            rest = value[:-len(unit)].rstrip()
            if rest:
                return rest, value[-len(unit):]
    return value, None


@dataclass(frozen=True)
class ShellOutput:
    """What one line did.

    status : {"ok", "info", "error", "empty", "exit"}
        ``ok`` the arm moved (or was shown), ``info`` text only, ``error`` nothing changed.
    text : str
        What was printed, as plain text.
    picture : Path or None
        The PNG written for this step.
    """

    status: str
    text: str
    picture: Optional[Path] = None


def parse_numbers(words: Iterable[str], lang: str = "en") -> list[float]:
    """Strictly parse number words, or simple arithmetic such as ``90/2`` (:mod:`armkit._arith`: numbers, pi,
    ``+ - * /``, parentheses; never ``eval``); no ``nan``/``inf``. Raise :class:`ParseError`."""
    from .._arith import evaluate, looks_arithmetic

    out = []
    for w in words:
        if _NUMBER_RE.match(w):
            x = float(w)
        elif looks_arithmetic(w):
            try:
                x = evaluate(w)
            except ValueError:
                raise ParseError(message("not_number", lang, word=_clip(w))) from None
        else:
            raise ParseError(message("not_number", lang, word=_clip(w)))
        if not math.isfinite(x):
            raise ParseError(message("not_finite", lang, word=_clip(w)))
        out.append(x)
    return out


def _split(text: str) -> list[str]:
    return [w for w in _SPLIT_RE.split(text.strip()) if w]


class Shell(ShellCommands):
    """An interactive kinematics session on one robot.

    Parameters
    ----------
    robot : Robot
    lang : str, optional
        Message language, a code of :data:`armkit.locale.LANGUAGES`; default from the locale.
    units : {"deg", "rad"}
        Angle units of input and output (``units`` changes them).
    plot : {"auto", "window", "png", "none"}
        ``auto``: a live window when a display exists, else PNG files.
    out_dir : path
        Where PNG pictures go (``step_001.png``, ...).
    session : bool
        Put the pictures in a subfolder of ``out_dir`` named after this session
        (``session-YYYYmmdd-HHMMSS-PID``), so two sessions never overwrite each other's
        pictures (the ``armkit shell`` command does this). A session writes at most
        :data:`MAX_PICTURES` pictures; past that it says so once and stops drawing.
    console : rich.console.Console, optional
        Where tables and messages are printed.
    """

    def __init__(self, robot: Robot, lang: Optional[str] = None, units: str = "deg", plot: str = "auto",
                 out_dir: str | Path = "out/shell", console: Any = None, session: bool = False,
                 mode: str = "ik") -> None:
        from rich.console import Console

        if mode not in ("ik", "fk"):
            raise ArgumentError.of("mode must be 'ik' or 'fk', got {mode!r}", mode=mode)
        self.mode = mode          # what numbers typed alone are: an IK target ("ik") or joint values ("fk")

        self.robot = robot
        self.lang = lang if lang is not None and lang in LANGUAGES else default_language()
        if units not in ("deg", "rad"):
            raise ArgumentError.of("units must be 'deg' or 'rad', got {units!r}", units=units)
        self.units = units
        if plot not in ("auto", "window", "png", "none"):
            raise ArgumentError.of("plot must be 'auto', 'window', 'png' or 'none', got {plot!r}", plot=plot)
        if plot == "auto":
            from ..viz._mpl import has_display

            plot = "window" if has_display() else "png"
        self.plot = plot
        self.out_dir = Path(out_dir)
        if session:
            import time

            self.out_dir = self.out_dir / f"session-{time.strftime('%Y%m%d-%H%M%S')}-{os.getpid()}"
        self.console = console if console is not None else Console(highlight=False)
        self.home = np.clip(np.zeros(robot.n), robot.lower, robot.upper)   # zeros, moved inside the limits
        self.q = self.home.copy()
        self.branch: Optional[str] = None      # the branch label of the current configuration
        self._branch_known = False             # self.branch computed for the current q
        self.preferred: Optional[str] = None   # the branch goto should use (None: nearest)
        self.step = 0
        self.pictures = 0
        self.view: Any = None    # armkit shell --view attaches a browser view here
        self._fig: Any = None
        self._names = {name.lower(): i for i, name in enumerate(robot.joint_names)}
        self._planar: Optional[bool] = None
        # the arm's surroundings: the one rule of armkit.collision.resolve_scene (the robot's own when its
        # file has them, else none); None: no check
        self.scene: Any = None
        if getattr(robot, "collision", None) is not None:
            from ..collision import resolve_scene

            self.scene = resolve_scene(robot, None)

    # ------------------------------------------------------------------ helpers
    @property
    def end_point(self) -> np.ndarray:
        """Current end point ``(3,)`` in the robot's unit."""
        return fk(self.robot, self.q)[:3, 3]

    def _joint_index(self, name: str) -> int:
        m = _INDEXED_RE.match(name)
        if name.lower() in self._names:
            return self._names[name.lower()]
        if m and 1 <= int(m.group(1)) <= self.robot.n:
            return int(m.group(1)) - 1
        raise ParseError(self._t("unknown_joint", name=name, names=name_list(self.robot.joint_names)))

    def _check_limits(self, q: np.ndarray) -> None:
        if not self.robot.limit_violations(q):
            return
        bad = []
        for j, v in zip(self.robot.joints, q):    # the same test as Robot.limit_violations, in the shell's units
            if v < j.lower - 1e-12 or v > j.upper + 1e-12:
                conv = (lambda x: x) if j.is_prismatic else self._angle_out
                bad.append(self._t("limit_item", joint=j.name, value=f"{conv(v):.6g}", lower=f"{conv(j.lower):g}",
                                   upper=f"{conv(j.upper):g}", unit=self.robot.unit if j.is_prismatic else self.units))
        raise ParseError(self._t("limit", detail=name_list(bad, limit=6, sep="; ")))

    # ------------------------------------------------------------------ parsing
    def _parse(self, stmt: str) -> tuple[str, Any]:
        """One statement -> (action, argument). Raises ParseError."""
        s = stmt.strip()
        low = s.lower()
        if low in EXIT_WORDS:
            return "exit", None
        if low in ("help", "?", "h"):
            return "help", None
        if low in ("limits", "limit"):
            return "limits", None
        if low in ("home", "zero"):
            return "q", self.home.copy()
        if low in ("show", "where", "state"):
            return "show", None
        m = _ASSIGN_RE.match(s)
        if m:
            k = self._joint_index(m.group(1))
            text, unit = _split_unit(m.group(2))
            value = parse_numbers([text], self.lang)[0]
            return "set", (k, self._angle_in(value, unit, k))
        if "=" in s and not s.lower().startswith("q"):
            name = s.split("=", 1)[0].strip()
            if re.match(r"^[A-Za-z_][A-Za-z_0-9\-]*$", name):
                self._joint_index(name)      # unknown joint -> its own message
            raise ParseError(self._t("not_number", word=_clip(s.split("=", 1)[1].strip())))
        m = _BRACKET_RE.match(s)
        if m:
            return "goto", parse_numbers(_split(m.group(1)), self.lang)
        m = _WORD_RE.match(s)
        if m:
            word, rest = m.group(1).lower(), (m.group(2) or "").strip()
            if word == "q":
                rest = rest[1:].strip() if rest.startswith("=") else rest
                values = parse_numbers(_split(rest), self.lang)
                if len(values) != self.robot.n:
                    raise ParseError(self._t("count", robot=self.robot.name, n=self.robot.n,
                                             names=name_list(self.robot.joint_names), k=len(values)))
                return "q", np.array([self._angle_in(v, None, i) for i, v in enumerate(values)])
            if word in ("goto", "go", "target", "ik"):
                return "goto", parse_numbers(_split(rest), self.lang)
            if word == "branch":
                return "branch", rest or None
            if word == "mode":
                return "mode", rest.lower() or None
            if word in ("units", "unit"):
                return "units", rest or None
            if word in ("lang", "language"):
                return "lang", rest or None
            if word in ("ground", "floor"):
                return "ground", parse_numbers(_split(rest), self.lang)
            if word == "box":
                return "box", parse_numbers(_split(rest), self.lang)
            if word in ("clear", "scene"):
                return word, None
        words = _split(s)
        if words and all(_NUMBER_RE.match(w) for w in words):
            if self.mode == "fk":                             # bare "30 45 60": joint values (mode fk)
                return self._parse("q " + " ".join(words))
            return "goto", parse_numbers(words, self.lang)   # bare "100 50 80": a target, as in the club's IK program
        raise ParseError(self._t("unknown", text=s if len(s) <= 60 else s[:57] + "..."))

    # ------------------------------------------------------------------ execute
    def execute(self, line: str) -> ShellOutput:
        """Run one input line; print its output and return what happened. Never raises for bad input."""
        from rich.console import Console
        from rich.text import Text

        buffer = io.StringIO()
        text_console = Console(file=buffer, width=110, no_color=True, highlight=False)
        outputs: list[Any] = []

        def emit(thing: Any, style: str = "") -> None:
            outputs.append((thing, style))

        status, picture = self._execute(line, emit)
        if status == "ok" and self.plot != "none":
            picture = self._draw(emit)
        if status == "ok" and getattr(self, "view", None) is not None:   # armkit shell --view: the browser follows
            self.view.set_q(self.q)
        from rich.table import Table

        from .common import natural_width

        for thing, style in outputs:
            if isinstance(thing, str):   # messages are plain text: never markup, no control characters
                thing = Text(shorten(plain(thing), MAX_MESSAGE), style=style)
            if isinstance(thing, Table) and natural_width(thing) > self.console.width:
                self._print_records(thing)      # too wide for the terminal: one record per row, nothing cut
            else:
                self.console.print(thing, style=style or None, soft_wrap=isinstance(thing, Text))
            text_console.print(thing, soft_wrap=isinstance(thing, Text))
        return ShellOutput(status, buffer.getvalue(), picture)

    def _execute(self, line: str, emit: Any) -> tuple[str, Optional[Path]]:
        if not isinstance(line, str):
            emit(self._t("unknown", text=_clip(repr(line))), "red")
            return "error", None
        if len(line) > MAX_LINE:
            emit(self._t("too_long", n=len(line), limit=MAX_LINE), "red")
            return "error", None
        statements = [s for s in line.replace("\x00", " ").split(";") if s.strip() and not s.strip().startswith("#")]
        if not statements:
            return "empty", None
        try:
            actions = [self._parse(s) for s in statements]
        except ParseError as exc:
            emit(str(exc), "red")
            return "error", None
        if any(a == "exit" for a, _ in actions[:-1]):
            emit(self._t("exit_alone"), "red")
            return "error", None
        # apply: joint settings first (atomically), then the other commands in order
        q_new = self.q.copy()
        moved = False
        status = "info"
        for action, arg in actions:
            if action == "set":
                q_new[arg[0]] = arg[1]
                moved = True
            elif action == "q":
                q_new = np.array(arg, dtype=float)
                moved = True
        if moved:
            try:
                self._check_limits(q_new)
                self._check_collision(q_new)
            except ParseError as exc:
                emit(str(exc), "red")
                return "error", None
            self.q = q_new
            self.branch, self._branch_known = self._identify_branch(), True
            status = "ok"
        for action, arg in actions:
            if action in ("set", "q"):
                continue
            try:
                with np.errstate(all="ignore"):  # absurd targets (1e308) overflow inside IK; the result says so
                    result = getattr(self, f"_cmd_{action}")(arg, emit)
            except ParseError as exc:
                emit(str(exc), "red")
                return "error", None
            if result == "exit":
                emit(self._t("bye"))
                return "exit", None
            if result == "error":
                return "error", None
            if result == "ok":
                status = "ok"
        if status == "ok":
            self._show(emit)
        return status, None

    def _print_records(self, table: Any) -> None:
        from rich.text import Text

        from .common import _split_long, table_records

        title, records = table_records(table)
        width = self.console.width
        if title:
            self.console.print(Text(title, style="bold"))
        for head, items in records:
            self.console.print(Text(head, style="bold"), soft_wrap=True)
            line = "  "
            for item in items:
                pieces = _split_long(item, width - 4)
                if line.strip() and (len(pieces) > 1 or len(line) + len(item) > width):
                    self.console.print(Text(line.rstrip()), soft_wrap=True)
                    line = "  "
                for piece in pieces[:-1]:
                    self.console.print(Text("  " + piece), soft_wrap=True)
                line += pieces[-1] + "  "
            if line.strip():
                self.console.print(Text(line.rstrip()), soft_wrap=True)
        if table.caption:
            self.console.print(Text.from_markup(str(table.caption)).plain)

    # ------------------------------------------------------------------ output
    def _show(self, emit: Any) -> None:
        from rich.table import Table


        r = self.robot
        T = fk(r, self.q)
        t = Table(title=esc(self._t("state_title", robot=r.name)), header_style="bold")
        t.add_column(self._t("joint"))
        t.add_column(self._t("value"), justify="right")
        t.add_column(self._t("limits"), justify="right")
        for i, j in enumerate(r.joints):
            u = r.unit if j.is_prismatic else self.units
            lo = j.lower if j.is_prismatic else self._angle_out(j.lower)
            hi = j.upper if j.is_prismatic else self._angle_out(j.upper)
            t.add_row(esc(j.name), f"{self._fmt_joint(i, self.q[i])} {u}", f"{lo:g} .. {hi:g} {u}")
        emit(t)
        p = T[:3, 3]
        rpy = [self._angle_out(v) for v in rotation_to_rpy(T[:3, :3])]
        if not self._branch_known:
            self.branch, self._branch_known = self._identify_branch(), True
        caption = esc(f"{self._t('branch')}: {self.branch}") if self.branch else None   # nothing when not known
        e = Table(title=None, header_style="bold", caption=caption)
        e.add_column("")
        for h in ("x / roll", "y / pitch", "z / yaw"):
            e.add_column(h, justify="right")
        e.add_row(f"{self._t('end_point')} ({r.unit})", *(f"{v:.6f}" for v in p))   # the one end-point line
        e.add_row(f"{self._t('orientation')} ({self.units})", *(f"{v:.4f}" for v in rpy))
        emit(e)

    def _draw(self, emit: Any) -> Optional[Path]:
        """Redraw the arm: update the window or write the next PNG. Returns the PNG path."""
        try:
            from ..viz._mpl import pyplot
            from ..viz.arm import plot_arm

            plt = pyplot()
            self.step += 1
            title = None
            if self.plot == "window":
                if self._fig is None or not plt.fignum_exists(self._fig.number):
                    plt.ion()
                    self._fig = None
                if self._fig is not None:
                    self._fig.clf()
                    from ..analysis.workspace import is_planar

                    ax = self._fig.add_subplot(111) if is_planar(self.robot) else \
                        self._fig.add_subplot(111, projection="3d")
                    plot_arm(self.robot, self.q, ax=ax, title=title)
                else:
                    self._fig = plot_arm(self.robot, self.q, title=title)
                self._fig.canvas.draw_idle()
                plt.pause(0.001)
                return None
            if self.pictures >= MAX_PICTURES:
                emit(self._t("picture_cap", limit=MAX_PICTURES), "yellow")
                self.plot = "none"
                return None
            fig = plot_arm(self.robot, self.q, title=title)
            path = self.out_dir / f"step_{self.step:03d}.png"
            from ..viz.plots import save_figure

            save_figure(fig, path, dpi=90)
            self.pictures += 1
            emit(self._t("picture", path=str(path)), "dim")
            return path
        except Exception as exc:  # noqa: BLE001 - drawing must never end the session
            emit(self._t("plot_failed", detail=f"{type(exc).__name__}: {exc}"), "yellow")
            self.plot = "none"
            return None

    # ------------------------------------------------------------------ loop
    def completions(self) -> list[str]:
        """Words offered by tab completion."""
        words = ["help", "exit", "quit", "q", "goto", "branch", "mode", "ik", "fk", "limits", "units", "deg", "rad",
                 "home", "show",
                 "ground", "box", "clear", "scene",
                 "lang", "auto", *LANGUAGES]
        words += [f"theta{i}" for i in range(1, self.robot.n + 1)] + list(self.robot.joint_names)
        res = self._all_branches(self._branch_target(self.q))
        if res is not None:
            words += [str(b) for b in np.asarray(res.branch)]
        return sorted(set(words))

    def run(self, stdin: Optional[TextIO] = None, history: Optional[str | Path] = None) -> int:
        """Read and execute lines until exit/quit/EOF. Returns the exit code (0).

        On a terminal, lines come from prompt_toolkit (history in ``history`` or
        ``~/.local/state/armkit/shell_history``, tab completion); otherwise plain lines
        from ``stdin``.
        """
        stdin = stdin if stdin is not None else sys.stdin
        from rich.text import Text

        self.console.print(Text(plain(self._t("welcome", robot=self.robot.name, n=self.robot.n,
                                              names=name_list(self.robot.joint_names), unit=self.robot.unit,
                                              angles=self.units))), soft_wrap=True)
        self.execute("show")
        read = self._prompt_reader() if stdin is sys.stdin and _isatty(stdin) else None
        while True:
            try:
                if read is not None:
                    line = read(f"{self.robot.name}> ")
                else:
                    line = stdin.readline()
                    if line == "":
                        raise EOFError
            except EOFError:
                self.console.print(self._t("bye"))
                return 0
            except KeyboardInterrupt:
                continue
            except UnicodeDecodeError as exc:   # a pipe that is not UTF-8: say so, keep reading
                self.console.print(Text(plain(self._t("internal", detail=f"input is not UTF-8: {exc.reason}")),
                                        style="red"))
                continue
            try:
                out = self.execute(line.rstrip("\n"))
            except Exception as exc:  # noqa: BLE001 - a bug must not end a user's session
                self.console.print(Text(shorten(plain(self._t("internal", detail=f"{type(exc).__name__}: {exc}"))),
                                        style="red"))
                continue
            if out.status == "exit":
                return 0

    def _prompt_reader(self) -> Any:
        try:
            from prompt_toolkit import PromptSession
            from prompt_toolkit.completion import WordCompleter
            from prompt_toolkit.history import FileHistory, InMemoryHistory
        except ImportError:
            return None
        state = Path(os.environ.get("XDG_STATE_HOME", Path.home() / ".local" / "state")) / "armkit"
        try:
            state.mkdir(parents=True, exist_ok=True)
            hist: Any = FileHistory(str(state / "shell_history"))
        except OSError:
            hist = InMemoryHistory()
        session: Any = PromptSession(history=hist)

        def read(prompt: str) -> str:
            completer = WordCompleter(self.completions(), ignore_case=True, sentence=False)
            return session.prompt(prompt, completer=completer)

        return read


def _isatty(stream: Any) -> bool:
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError):
        return False
