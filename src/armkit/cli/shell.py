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
history and tab completion on a terminal, plain lines from a pipe).

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
from ..errors import ArgumentError, ArmkitError, ParseError
from ..locale import LANGUAGES, N_, default_language, message, translate
from ..kinematics import fk
from ..model.robot import Robot
from .common import VECTOR_SPLIT

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


class Shell:
    """An interactive kinematics session on one robot.

    Parameters
    ----------
    robot : Robot
    lang : {"en", "ko"}, optional
        Message language; default from the locale.
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
            raise ArgumentError(f"mode must be 'ik' or 'fk', got {mode!r}")
        self.mode = mode          # what numbers typed alone are: an IK target ("ik") or joint values ("fk")

        self.robot = robot
        self.lang = lang if lang in LANGUAGES else default_language()
        if units not in ("deg", "rad"):
            raise ArgumentError(f"units must be 'deg' or 'rad', got {units!r}")
        self.units = units
        if plot not in ("auto", "window", "png", "none"):
            raise ArgumentError(f"plot must be 'auto', 'window', 'png' or 'none', got {plot!r}")
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
    def _t(self, key: str, **fields: object) -> str:
        return message(key, self.lang, **fields)

    @property
    def end_point(self) -> np.ndarray:
        """Current end point ``(3,)`` in the robot's unit."""
        return fk(self.robot, self.q)[:3, 3]

    @property
    def planar(self) -> bool:
        if self._planar is None:
            from ..analysis.workspace import is_planar

            self._planar = is_planar(self.robot)
        return self._planar

    def _angle_in(self, value: float, unit: Optional[str], joint: int) -> float:
        """A typed value for ``joint`` in internal units (rad / length)."""
        j = self.robot.joints[joint]
        u = (unit or "").lower()
        if j.is_prismatic:
            if u in ("", self.robot.unit):
                return value
            scale = {"m": 1.0, "cm": 1e-2, "mm": 1e-3}
            if u in scale:
                return value * scale[u] / self.robot.unit_scale
            raise ParseError(self._t("bad_unit", unit=unit, joint=j.name, kind=j.kind))
        if u in ("mm", "cm", "m"):
            raise ParseError(self._t("bad_unit", unit=unit, joint=j.name, kind=j.kind))
        if u.startswith("rad"):
            return value
        if u:  # deg, degree(s), °
            return math.radians(value)
        return math.radians(value) if self.units == "deg" else value

    def _angle_out(self, value: float) -> float:
        return math.degrees(value) if self.units == "deg" else value

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

    def _unreachable(self, message_: str, reason: str, error: float) -> str:
        """Why a target was not reached: the solver's sentence in English; in Korean the reason and the
        position error of the closest configuration (the solvers' sentences are English)."""
        if self.lang == "en":
            return message_ or reason
        return self._t("unreachable_detail", reason=reason, error=f"{error:.4g} {self.robot.unit}", message=message_)

    def _check_collision(self, q: np.ndarray) -> None:
        """Refuse ``q`` when the arm would collide with the scene, its body or itself."""
        if self.scene is None:
            return
        from ..collision import collisions

        hits = collisions(self.robot, q, self.scene).colliding_pairs()
        if hits:
            a, b, depth = hits[0]
            raise ParseError(self._t("collision", a=a.replace("_", " "), b=b.replace("_", " "),
                                     depth=f"{depth:.3g} {self.robot.unit}"))

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

    # ------------------------------------------------------------------ commands
    def _cmd_exit(self, arg: Any, emit: Any) -> str:
        return "exit"

    def _set_scene(self, scene: Any, emit: Any) -> str:
        from ..collision import collisions

        self.scene = scene
        names = ", ".join(s.describe() if s.name in (s.kind, "ground") else f"{s.name} ({s.describe()})"
                          for s in scene)
        emit(self._t("scene_now", shapes=names) if names else self._t("scene_none"))
        now = collisions(self.robot, self.q, scene).message()
        if now:
            emit(self._t("scene_hit", detail=now), "yellow")
        return "info"

    def _empty_scene(self) -> Any:
        from ..collision import Scene

        return self.scene if self.scene is not None else Scene([], self.robot.unit)

    def _cmd_scene(self, arg: Any, emit: Any) -> str:
        return self._set_scene(self._empty_scene(), emit)

    def _cmd_clear(self, arg: Any, emit: Any) -> str:
        from ..collision import Scene

        return self._set_scene(Scene([], self.robot.unit), emit)

    def _cmd_ground(self, values: list[float], emit: Any) -> str:
        from ..collision import Scene

        if len(values) != 1:
            raise ParseError(self._t("ground_count", unit=self.robot.unit, k=len(values)))
        floor = Scene.plane([0.0, 0.0, 1.0], values[0], name="ground")
        return self._set_scene(self._empty_scene().without("ground").with_shape(floor), emit)

    def _cmd_box(self, values: list[float], emit: Any) -> str:
        from ..collision import Scene, SceneError

        if len(values) != 6:
            raise ParseError(self._t("box_count", unit=self.robot.unit, k=len(values)))
        lo, hi = np.minimum(values[:3], values[3:]), np.maximum(values[:3], values[3:])
        scene = self._empty_scene()
        name = f"box {sum(s.kind == 'box' for s in scene) + 1}"
        try:
            box = Scene.box(0.5 * (lo + hi), hi - lo, name=name)
        except SceneError as exc:
            raise ParseError(str(exc)) from None
        return self._set_scene(scene.with_shape(box), emit)

    def _cmd_help(self, arg: Any, emit: Any) -> str:
        emit(self._t("help", unit=self.robot.unit, first=self.robot.joint_names[0], goto=self._goto_example()))
        emit(esc(translate(N_("  mode ik|fk                    numbers typed alone: a target (ik) or joint values (fk); "
                              "now {mode}"), self.lang, mode=self.mode)))
        return "info"

    def _cmd_show(self, arg: Any, emit: Any) -> str:
        return "ok"

    def _cmd_limits(self, arg: Any, emit: Any) -> str:
        from rich.table import Table

        t = Table(title=esc(self._t("limits_title", robot=self.robot.name)), header_style="bold")
        for col in (self._t("joint"), self._t("limits")):
            t.add_column(col)
        for j in self.robot.joints:
            if j.is_prismatic:
                t.add_row(esc(j.name), f"{j.lower:g} .. {j.upper:g} {self.robot.unit}")
            else:
                lo, hi = self._angle_out(j.lower), self._angle_out(j.upper)
                t.add_row(esc(j.name), f"{lo:g} .. {hi:g} {self.units}")
        emit(t)
        return "info"

    def _cmd_units(self, arg: Optional[str], emit: Any) -> str:
        if arg is not None:
            u = arg.strip().lower()
            u = {"degree": "deg", "degrees": "deg", "°": "deg", "radian": "rad", "radians": "rad"}.get(u, u)
            if u not in ("deg", "rad"):
                raise ParseError(self._t("units_bad", u=arg))
            self.units = u
        emit(self._t("units_now", u=self.units))
        return "info"

    def _cmd_lang(self, arg: Optional[str], emit: Any) -> str:
        if arg is not None:
            u = arg.strip().lower()
            if u not in LANGUAGES:
                raise ParseError(self._t("lang_bad", u=arg))
            self.lang = u
        emit(self._t("lang_now"))
        return "info"

    def _goto_example(self) -> str:
        if self.planar:
            return "x y" if self.robot.n == 2 else "x y [phi]"
        return "x y z" if self.robot.n < 6 else "x y z [roll pitch yaw]"

    def _branch_target(self, q: np.ndarray) -> np.ndarray:
        """The target whose closed-form branches name the configurations (position or pose)."""
        T = fk(self.robot, q)
        if self.planar:
            return T if self.robot.n >= 3 else T[:2, 3]
        return T if self.robot.n >= 6 else T[:3, 3]

    def _scene_arg(self) -> Any:
        """The shell's scene as the library's ``scene=`` (False: no check)."""
        return False if self.scene is None else self.scene

    def _checked_note(self, emit: Any) -> None:
        """"checked against: ground, torso" after an answer that was checked for collisions (as the CLI prints)."""
        if self.scene is None:
            return
        from ..collision import checked_against

        from .common import _CHECKED_WORDS

        names = [translate(n, self.lang) if n in _CHECKED_WORDS else n for n in checked_against(self.robot, self.scene)]
        emit(esc(translate(N_("checked against: {names}"), self.lang, names=", ".join(names))), "dim")

    def _all_branches(self, target: np.ndarray) -> Optional[Any]:
        """``ik_all`` of ``target`` from the current q, or None when the arm has no closed form."""
        try:
            from .. import ik_all  # type: ignore[attr-defined]
        except ImportError:
            return None
        try:
            return ik_all(self.robot, target, q0=self.q, scene=self._scene_arg())
        except (ArmkitError, ValueError, NotImplementedError):
            return None

    def _identify_branch(self) -> Optional[str]:
        res = self._all_branches(self._branch_target(self.q))
        if res is None:
            return None
        d = np.abs(np.angle(np.exp(1j * (np.asarray(res.q) - self.q))))
        d = np.where(self.robot.prismatic, np.abs(np.asarray(res.q) - self.q), d).max(axis=-1)
        ok = np.asarray(res.success) & (d < 1e-6)
        if not ok.any():
            return None
        return str(np.asarray(res.branch)[int(np.argmax(ok))])

    def _cmd_branch(self, arg: Optional[str], emit: Any) -> str:
        res = self._all_branches(self._branch_target(self.q))
        if res is None:
            emit(self._t("no_branches", robot=self.robot.name), "yellow")
            return "info"
        names = [str(b) for b in np.asarray(res.branch)]
        if arg is None:
            from rich.table import Table

            t = Table(title=self._t("branches_title"), header_style="bold")
            t.add_column(self._t("branch"))
            for name in self.robot.joint_names:
                t.add_column(f"{esc(name)} ({self.units})", justify="right")
            t.add_column(self._t("ok"))
            for b, name in enumerate(names):
                qb = self._wrapped(np.asarray(res.q)[b])
                mark = "*" if name == self.branch else ""
                t.add_row(esc(name + mark), *(self._fmt_joint(i, v) for i, v in enumerate(qb)),
                          self._t("yes") if bool(np.asarray(res.success)[b])
                          else esc(self._t("term", term=str(np.asarray(res.reason)[b]))))
            emit(t)
            self._checked_note(emit)
            return "info"
        want = arg.strip()
        if want.lower() == "auto":
            self.preferred = None
            emit(self._t("branch_auto"))
            return "info"
        match = [n for n in names if n.lower() == want.lower()]
        if not match:
            raise ParseError(self._t("branch_unknown", name=_clip(want), names=name_list(names)))
        self.preferred = match[0]
        emit(self._t("branch_set", name=match[0]))
        b = names.index(match[0])
        if bool(np.asarray(res.success)[b]):
            self.q = np.asarray(res.q)[b].astype(float)
            self.branch, self._branch_known = match[0], True
            return "ok"
        emit(self._t("branch_missing", name=match[0], current=self.branch or self._t("none")), "yellow")
        return "info"

    def _goto_target(self, values: list[float]) -> tuple[np.ndarray, Optional[float]]:
        """Target array (and planar end angle) from typed numbers; ParseError on a wrong count."""
        k = len(values)
        if self.planar:
            if k == 2:
                phi = None
                if self.robot.n >= 3:  # keep the current end angle
                    T = fk(self.robot, self.q)
                    phi = math.atan2(T[1, 0], T[0, 0])
                return np.array(values, dtype=float), phi
            if k == 3 and self.robot.n >= 3:
                return np.array(values[:2], dtype=float), self._angle_in(values[2], None, 0) if not \
                    self.robot.prismatic[0] else math.radians(values[2])
            forms = self._t("forms_planar" if self.robot.n < 3 else "forms_planar_phi")
        else:
            if k == 3:
                return np.array(values, dtype=float), None
            if k == 6:
                from ..spatial import make_pose, rpy_to_rotation

                rpy = [v if self.units == "rad" else math.radians(v) for v in values[3:]]
                return make_pose(rpy_to_rotation(rpy), values[:3]), None
            forms = self._t("forms_spatial")
        raise ParseError(self._t("goto_count", robot=self.robot.name, forms=forms, k=k))

    def _cmd_goto(self, values: list[float], emit: Any) -> str:
        target, phi = self._goto_target(values)
        try:
            from .. import ik, ik_all  # type: ignore[attr-defined]
        except ImportError as exc:  # the IK package not built yet
            emit(self._t("ik_error", detail=str(exc)), "red")
            return "error"
        kwargs: dict[str, Any] = {"phi": phi} if phi is not None else {}
        try:
            try:
                res = ik_all(self.robot, target, q0=self.q, scene=self._scene_arg(), **kwargs)
            except (ArmkitError, ValueError, NotImplementedError):
                res = None
            if res is not None:
                ok = np.asarray(res.success)
                names = [str(b) for b in np.asarray(res.branch)]
                if not ok.any():
                    detail = self._unreachable(str(np.asarray(res.message)[0]), str(np.asarray(res.reason)[0]),
                                               float(np.asarray(res.position_error)[0]))
                    emit(self._t("unreachable", detail=detail), "red")
                    if "collision" in np.asarray(res.reason).tolist():
                        self._checked_note(emit)
                    return "error"
                pick = int(np.argmax(ok))                      # sorted by distance to the current q
                if self.preferred in names and ok[names.index(self.preferred)]:
                    pick = names.index(self.preferred)
                self.q = np.asarray(res.q)[pick].astype(float)
                self.branch, self._branch_known = names[pick], True
                note = str(np.asarray(res.message)[pick])
                if note:    # what the CLI's ik prints too: "yaw is free", "elbow-up and elbow-down coincide" ...
                    from ..locale.library import ik_explanation

                    text = ik_explanation(str(np.asarray(res.reason)[pick]), note,
                                          float(np.asarray(res.position_error)[pick]), self.robot.unit, self.lang)
                    emit(esc(translate(N_("note: {text}"), self.lang, text=text)), "dim")
                self._checked_note(emit)
                return "ok"
            one = ik(self.robot, target, q0=self.q, scene=self._scene_arg(), **kwargs)
        except (ArmkitError, ValueError, FloatingPointError) as exc:
            emit(self._t("ik_error", detail=str(exc)), "red")
            return "error"
        if not bool(np.asarray(one.success)):
            detail = self._unreachable(str(one.message), str(np.asarray(one.reason)),
                                       float(np.asarray(one.position_error)))
            emit(self._t("unreachable", detail=detail), "red")
            if str(np.asarray(one.reason)) == "collision":
                self._checked_note(emit)
            return "error"
        self.q = np.asarray(one.q, dtype=float)
        self.branch, self._branch_known = str(np.asarray(one.branch)) or None, True
        self._checked_note(emit)
        return "ok"

    # ------------------------------------------------------------------ output
    def _fmt_joint(self, i: int, v: float) -> str:
        if self.robot.prismatic[i]:
            return f"{v:.4f}"
        shown = f"{self._angle_out(v):.4f}" if self.units == "deg" else f"{v:.6f}"
        return shown[1:] if shown.startswith("-") and not shown.strip("-0.") else shown    # no "-0.0000"

    def _wrapped(self, q: np.ndarray) -> np.ndarray:
        """Revolute angles of a branch (a failed one may come back as 214 deg) in (-180, 180] deg, or shifted by a
        turn into the joint limits where that fits them."""
        r = self.robot
        w = np.where(r.prismatic, q, -np.angle(np.exp(-1j * np.asarray(q, dtype=float))))   # (-pi, pi]
        for shift in (2 * math.pi, -2 * math.pi):
            moved = w + shift
            w = np.where(~r.prismatic & ((w < r.lower) | (w > r.upper)) & (moved >= r.lower) & (moved <= r.upper),
                         moved, w)
        return w

    def _cmd_mode(self, arg: Optional[str], emit: Any) -> str:
        if arg is None:
            emit(esc(translate(N_("mode {mode}: numbers typed alone are {meaning}"), self.lang, mode=self.mode,
                               meaning=self._mode_meaning())))
            return "info"
        if arg not in ("ik", "fk"):
            raise ParseError(translate(N_("mode takes ik (numbers alone are a target) or fk (numbers alone are joint "
                                          "values), got {word!r}"), self.lang, word=_clip(arg)))
        self.mode = arg
        emit(esc(translate(N_("mode {mode}: numbers typed alone are {meaning}"), self.lang, mode=self.mode,
                           meaning=self._mode_meaning())))
        return "info"

    def _mode_meaning(self) -> str:
        return translate(N_("a target ({goto})"), self.lang, goto=self._goto_example()) if self.mode == "ik" else \
            translate(N_("joint values ({n})"), self.lang, n=self.robot.n)

    def _show(self, emit: Any) -> None:
        from rich.table import Table

        from ..spatial import rotation_to_rpy

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
                 "lang", "auto", "en", "ko"]
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


def _clip(text: str, limit: int = 60) -> str:
    """A piece of user input short enough to quote in a message."""
    return text if len(text) <= limit else text[:limit - 3] + "..."


def _isatty(stream: Any) -> bool:
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError):
        return False
