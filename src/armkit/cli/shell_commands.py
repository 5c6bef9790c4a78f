"""The commands of the interactive shell (:mod:`armkit.cli.shell`): what each statement does once parsed.

:class:`ShellCommands` is the base of :class:`~armkit.cli.shell.Shell`. It holds the
``_cmd_<action>`` method of every action the shell's grammar produces (``goto``, ``branch``,
``mode``, ``ground``, ``box``, ``clear``, ``scene``, ``help``, ``show``, ``limits``,
``units``, ``lang``, ``exit``) and the helpers they share: unit conversion, joint
formatting, the scene and the IK branches. :meth:`Shell._execute` calls
``_cmd_<action>(arg, emit)``; each returns ``"ok"`` (the arm moved or is shown), ``"info"``
(text only), ``"error"`` or ``"exit"``, and raises :class:`~armkit.errors.ParseError` for an
argument it refuses (nothing changes then). The state (``robot``, ``q``, ``units`` ...) is
set by :meth:`Shell.__init__`.

Adding a command: a word in ``Shell._parse`` that returns ``(action, argument)``, a
``_cmd_<action>`` method here, its word in ``Shell.completions`` and its line in the help
text (``locale``).
"""

from __future__ import annotations

import math
from typing import Any, Optional

import numpy as np

from .._text import esc, name_list
from ..errors import ArmkitError, ParseError
from ..ik import ik, ik_all
from ..kinematics import fk
from ..locale import LANGUAGES, N_, SOURCE, message, translate
from ..model.robot import Robot
from ..spatial import make_pose, rpy_to_rotation

__all__ = ["ShellCommands"]


def _clip(text: str, limit: int = 60) -> str:
    """A piece of user input short enough to quote in a message."""
    return text if len(text) <= limit else text[:limit - 3] + "..."


class ShellCommands:
    """The commands and shared helpers of :class:`~armkit.cli.shell.Shell` (which sets this state)."""

    robot: Robot
    lang: str
    units: str                  # "deg" or "rad": angles typed and shown
    mode: str                   # "ik" or "fk": what numbers typed alone are
    q: np.ndarray               # the current configuration (rad / length units)
    branch: Optional[str]       # the branch label of the current configuration
    _branch_known: bool         # branch computed for the current q
    preferred: Optional[str]    # the branch goto should use (None: nearest)
    scene: Any                  # the collision scene (None: no check)
    _planar: Optional[bool]

    # ------------------------------------------------------------------ helpers
    def _t(self, key: str, **fields: object) -> str:
        return message(key, self.lang, **fields)

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

    def _unreachable(self, message_: str, reason: str, error: float) -> str:
        """Why a target was not reached: the solver's sentence in English; in Korean the reason and the
        position error of the closest configuration (the solvers' sentences are English)."""
        if self.lang == SOURCE:
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

    # ------------------------------------------------------------------ commands
    def _cmd_exit(self, arg: Any, emit: Any) -> str:
        return "exit"

    def _set_scene(self, scene: Any, emit: Any) -> str:
        from ..collision import collisions

        from ..locale.library import localize   # a shape's description and the collision: the shell's language

        self.scene = scene
        names = ", ".join(localize(s.describe(), self.lang) if s.name in (s.kind, "ground")
                          else f"{s.name} ({localize(s.describe(), self.lang)})" for s in scene)
        emit(self._t("scene_now", shapes=names) if names else self._t("scene_none"))
        now = collisions(self.robot, self.q, scene).message()
        if now:
            emit(self._t("scene_hit", detail=localize(now, self.lang)), "yellow")
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
        emit(self._t("help", unit=self.robot.unit, first=self.robot.joint_names[0], goto=self._goto_example(),
                     languages="|".join(LANGUAGES)))
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
                raise ParseError(self._t("lang_bad", u=arg, languages=", ".join(LANGUAGES)))
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
                rpy = [v if self.units == "rad" else math.radians(v) for v in values[3:]]
                return make_pose(rpy_to_rotation(rpy), values[:3]), None
            forms = self._t("forms_spatial")
        raise ParseError(self._t("goto_count", robot=self.robot.name, forms=forms, k=k))

    def _cmd_goto(self, values: list[float], emit: Any) -> str:
        target, phi = self._goto_target(values)
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
