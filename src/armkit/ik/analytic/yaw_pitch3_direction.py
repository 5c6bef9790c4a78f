"""Yaw + three parallel pitch axes + roll (the SO-101): the position with a pointing direction of the tool's z axis.

Split from :mod:`.yaw_pitch3` (the closed form for a position and a tool pitch), whose names it
uses; :mod:`.yaw_pitch3` still answers for the names defined here (``yaw_pitch3.solve_direction``
works), loading this module on first use. A yaw + three pitch joints + roll arm points its
approach axis only within its vertical plane, so a direction is a pitch
(:func:`direction_to_pitch`) in a plane the roll's sideways offset must put through the target
(:func:`_roll_candidates`); :func:`solve_direction` takes the closed form of
:func:`.yaw_pitch3.solve_pitch` for that pitch and roll, then Gauss-Newton on (position,
direction) over the five joints of the true model (:func:`_polish_direction`). The compiled
counterpart is ``_yaw_pitch3_jit.direction_branches`` / ``nearest_direction_rows``.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from ...kinematics import fk, jacobian
from ...model.robot import Robot
from ..result import IKResult, default_tolerance
from ._common import Array
from .yaw_pitch3 import (_LABELS, _LATERAL_SLACK, _REASON_TEXT, YawPitch3, _cross, _geometry, pitch_range_text,
                         reachable_pitches, shoulder_reach, solve_pitch)

__all__ = ["solve_direction", "direction_to_pitch"]


# ------------------------------------------------------------------------ position + pointing direction
_VERTICAL = 1e-6    # a direction whose horizontal part is below this points straight up or down


def _direction_check(robot: Robot, q: Array, pts: Array, dirs: Array, tol: tuple[float, float],
                     enforce_limits: bool):
    """Position error, angle (rad) between the tool's z axis and ``dirs``, ok, within limits; ``q`` (..., n)."""
    T = fk(robot, q)
    dp = np.linalg.norm(T[..., :3, 3] - pts, axis=-1)
    z = T[..., :3, 2]
    ang = np.arctan2(np.linalg.norm(_cross(z, dirs), axis=-1), np.einsum("...i,...i->...", z, dirs))
    within = np.all((q >= robot.lower - 1e-12) & (q <= robot.upper + 1e-12), axis=-1)
    ok = (dp <= tol[0]) & (ang <= tol[1]) & (within | (not enforce_limits))
    return dp, ang, ok, within


def _direction_residual(robot: Robot, q: Array, pts: Array, dirs: Array) -> tuple[Array, Array]:
    T = fk(robot, q)
    return np.concatenate([pts - T[:, :3, 3], dirs - T[:, :3, 2]], axis=1), T[:, :3, 2]


def _polish_direction(robot: Robot, q: Array, pts: Array, dirs: Array, steps: int = 12) -> Array:
    """Gauss-Newton on (position, tool z axis along ``dirs``) over every joint, rows ``q`` ``(R, n)``.

    Near straight up or down the roll moves the tool's z axis by micro-radians only: a step is
    cut to 0.3 rad at most and halved until it lowers the error (up to 8 times)."""
    q = q.copy()
    n = robot.n
    eye = np.eye(n)
    w = np.array([1.0, 1.0, 1.0, 0, 0, 0]) / robot.reach + np.array([0, 0, 0, 1.0, 1.0, 1.0])
    active = np.arange(len(q))
    for _ in range(steps):
        if len(active) == 0:
            break
        e, z = _direction_residual(robot, q[active], pts[active], dirs[active])
        cost = np.sum((e * w) ** 2, axis=1)
        still = cost > 1e-32
        active, e, z, cost = active[still], e[still], z[still], cost[still]
        if len(active) == 0:
            break
        Jf = jacobian(robot, q[active])
        J = np.empty((len(active), 6, n))
        J[:, :3] = Jf[:, :3]
        zz = np.broadcast_to(z[:, None, :], (len(active), n, 3))
        J[:, 3:] = -np.swapaxes(_cross(zz, np.swapaxes(Jf[:, 3:], 1, 2)), 1, 2)     # dz = w x z = -z x w
        Jw, ew = J * w[None, :, None], e * w
        JT = np.swapaxes(Jw, 1, 2)
        dq = np.linalg.solve(JT @ Jw + 1e-14 * eye, JT @ ew[..., None])[..., 0]
        big = np.abs(dq).max(axis=1)
        dq *= np.minimum(1.0, 0.3 / np.maximum(big, 1e-300))[:, None]
        todo = np.arange(len(active))
        for _half in range(8):
            qn = q[active[todo]] + dq[todo]
            en, _ = _direction_residual(robot, qn, pts[active[todo]], dirs[active[todo]])
            better = np.sum((en * w) ** 2, axis=1) < cost[todo]
            q[active[todo[better]]] = qn[better]
            todo = todo[~better]
            if len(todo) == 0:
                break
            dq[todo] *= 0.5
        active = np.setdiff1d(active, active[todo]) if len(todo) else active
    return q


def direction_to_pitch(robot: Robot, pts: Array, dirs: Array) -> tuple[Array, Array]:
    """The pitch (rad) of pointing directions ``dirs`` ``(B, 3)`` at points ``pts``, and how far (rad) each
    direction leaves the vertical plane through the yaw axis and the point (0 for straight up or down)."""
    u, o, _ = _geometry(robot)
    w = pts - o
    up = dirs @ u
    dh = dirs - up[:, None] * u
    nh = np.linalg.norm(dh, axis=-1)
    wh = w - (w @ u)[:, None] * u
    nw = np.linalg.norm(wh, axis=-1)
    outward = np.where((np.einsum("bi,bi->b", dh, wh) < 0), -1.0, 1.0)
    psi = np.where(nh > _VERTICAL, np.arctan2(up, outward * nh), np.where(up < 0, -0.5 * math.pi, 0.5 * math.pi))
    radial = wh / np.maximum(nw, 1e-300)[:, None]
    side = np.abs(np.einsum("bi,bi->b", dh, _cross(u[None, :], radial)))
    off = np.where((nh > _VERTICAL) & (nw > 1e-12 * robot.reach), np.arcsin(np.clip(side, 0.0, 1.0)), 0.0)
    return psi, off


_NEAR_VERTICAL = 1e-4   # below this horizontal part (chain frame) the roll is found by a sweep on the true model
_ROLL_SWEEP = 24


def _roll_candidates(robot: Robot, solver: YawPitch3, pts: Array, dirs: Array, q0: Array
                     ) -> tuple[Array, NDArray[np.bool_]]:
    """Roll joint values ``(B, K)`` to start from (and which are valid).

    A direction with a horizontal part fixes the arm's plane (front or back); the roll's
    sideways offset must then put that plane through the target: two rolls each way. Nearly
    straight up or down, the plane is free and the roll is set by micro-radian effects (the
    tool's z axis leaves the roll axis by the file's rounding): a sweep of rolls over the
    limits, each then polished on the true model.
    """
    sf = solver.sf
    B = len(pts)
    if not solver.roll:
        return np.zeros((B, 1)), np.ones((B, 1), dtype=bool)
    theta5 = float(sf.theta[4])
    p0 = sf.point_to_chain(pts)
    d0 = dirs @ sf.base_inv[:3, :3].T
    vertical = np.hypot(d0[:, 0], d0[:, 1]) <= _NEAR_VERTICAL
    K = _ROLL_SWEEP if vertical.any() else 4
    cand = np.repeat(q0[:, -1:], K, axis=1)
    valid = np.zeros((B, K), dtype=bool)
    if vertical.any():
        lo, hi = float(robot.lower[4]), float(robot.upper[4])
        lo, hi = (lo, hi) if math.isfinite(lo) and math.isfinite(hi) else (-math.pi, math.pi)
        cand[vertical] = lo + (hi - lo) * (np.arange(K) + 0.5) / K
        valid[vertical] = True
    s4 = float(solver.sf.twist(3) or 1)
    t = sf.tool[:3, 3]
    A, t_ang = math.hypot(t[0], t[1]), math.atan2(t[1], t[0])
    gamma = np.arctan2(d0[:, 1], d0[:, 0])
    for k, turn in enumerate((0.0, math.pi)):            # the arm's plane along the direction, either way
        phi1 = gamma + turn
        z1 = solver.s1 * np.stack([np.sin(phi1), -np.cos(phi1)], axis=1)
        L = np.einsum("bi,bi->b", p0[:, :2], z1)
        if A < 1e-12 * sf.scale:
            ok = ~vertical & (np.abs(L - solver.lateral0) <= _LATERAL_SLACK * sf.scale)
            valid[ok, 2 * k] = True
            continue
        r = s4 * (L - solver.lateral0) / A
        ok = ~vertical & (np.abs(r) <= 1.0 + 1e-3)      # the file's rounding moves L by ~1e-6 m
        a = np.arcsin(np.clip(r, -1.0, 1.0))
        cand[ok, 2 * k] = (a - t_ang - theta5)[ok]
        cand[ok, 2 * k + 1] = (math.pi - a - t_ang - theta5)[ok]
        valid[ok, 2 * k:2 * k + 2] = True
    cand = np.remainder(cand + math.pi, 2 * math.pi) - math.pi
    return cand, valid


def solve_direction(robot: Robot, solver: YawPitch3, pts: Array, dirs: Array, q0: Array,
                    tol: tuple[float, float] | None = None, enforce_limits: bool = True) -> IKResult:
    """Every branch for positions ``pts`` ``(B, 3)`` with the tool's z axis along unit ``dirs`` ``(B, 3)``.

    A yaw + three pitch joints + roll arm points its approach axis only within its vertical
    plane, so a direction is a pitch (:func:`direction_to_pitch`) and the plane's yaw: the
    closed form :func:`solve_pitch` for that pitch, with the roll that makes it exact (the
    tool's z axis leaves the roll axis by the file's rounding, and the roll moves the tool
    point sideways: :func:`_roll_candidates`), then Gauss-Newton on (position, direction)
    over all the joints of the true model. Per branch label (front/back x elbow) the
    solution nearest ``q0`` that succeeds; ``rotation_error`` is the angle between the
    tool's z axis and the direction. Fields ``(B, 4)``, ``q`` ``(B, 4, n)``, sorted like
    :func:`solve_pitch`.
    """
    if tol is None:
        tol = default_tolerance(robot)
    B, n = len(pts), robot.n
    psi, off = direction_to_pitch(robot, pts, dirs)
    rolls, valid = _roll_candidates(robot, solver, pts, dirs, q0)
    K = rolls.shape[1]
    q0k = np.repeat(q0[:, None, :], K, axis=1)
    if solver.roll:
        q0k[..., 4] = rolls
    flat = q0k.reshape(-1, n)
    rep = lambda a: np.repeat(a, K, axis=0)  # noqa: E731
    res = solve_pitch(robot, solver, rep(pts), rep(psi), flat, tol, enforce_limits=False, sweep=False)
    q = np.asarray(res.q).reshape(B * K * 4, n)
    pk, dk = np.repeat(rep(pts), 4, axis=0), np.repeat(rep(dirs), 4, axis=0)
    close = (np.asarray(res.position_error).reshape(-1) <= 6e-3 * robot.reach) & np.repeat(valid.reshape(-1), 4)
    if close.any():
        q[close] = _polish_direction(robot, q[close], pk[close], dk[close], 40)
        from . import wrap_to_limits

        q[close] = wrap_to_limits(q[close][:, None, :], np.repeat(rep(q0), 4, axis=0)[close][:, None, :],
                                  robot.lower, robot.upper, ~robot.prismatic)[:, 0]
    dp, ang, ok, within = _direction_check(robot, q, pk, dk, tol, enforce_limits)
    ok &= close
    labels = np.asarray(res.branch).reshape(B, K * 4)
    q = q.reshape(B, K * 4, n)  # type: ignore[assignment]
    dp, ang, ok, within, close = (a.reshape(B, K * 4) for a in (dp, ang, ok, within, close))
    msg_pitch = np.asarray(res.message, dtype=object).reshape(B, K * 4)
    dist = np.linalg.norm(q - q0[:, None, :], axis=-1)
    fk_ok = (dp <= tol[0]) & (ang <= tol[1]) & close
    # per label: success, then right but outside the limits, then the nearest miss; nearest q0 among equals
    rank = np.where(ok, 0.0, np.where(fk_ok, 1e6, 2e6 + 1e3 * dp / robot.reach)) + dist
    out_q = np.empty((B, 4, n))
    fields = {k: np.empty((B, 4), dtype=t) for k, t in (("dp", float), ("ang", float), ("ok", bool),
                                                         ("within", bool), ("fk", bool), ("msg", object))}
    for j, lab in enumerate(_LABELS):
        r = np.where(labels == lab, rank, np.inf)
        pick = np.argmin(r, axis=1)
        rows = np.arange(B)
        out_q[:, j] = q[rows, pick]
        for key, src in (("dp", dp), ("ang", ang), ("ok", ok), ("within", within), ("fk", fk_ok),
                         ("msg", msg_pitch)):
            fields[key][:, j] = src[rows, pick]
    code = np.where(fields["ok"], 0, np.where(fields["fk"] & ~fields["within"], 2, 1))
    message = np.full((B, 4), "", dtype=object)
    names = robot.joint_names
    none_valid = ~valid.any(axis=1)
    for b in np.flatnonzero(~fields["ok"].any(axis=1)):
        if none_valid[b]:  # type: ignore[index]
            head = (f"this arm points the tool only within its vertical plane through the target (the sideways "
                    f"offset allows a little more); the direction leaves that plane by {math.degrees(off[b]):.3g} deg")
        else:
            head = f"the direction is pitch {math.degrees(psi[b]):.4g} deg at this point"
        for j in range(4):
            if code[b, j] == 2:
                bad = ", ".join(nm for k, nm in enumerate(names)
                                if not robot.lower[k] - 1e-12 <= out_q[b, j, k] <= robot.upper[k] + 1e-12)
                tail = f"outside the joint limits: {bad} (see armkit info for the limits)."
            elif none_valid[b]:  # type: ignore[index]
                tail = "unreachable."
            else:
                tail = str(fields["msg"][b, j]) or (f"unreachable: the closest configuration of this branch misses "
                                                    f"by {fields['dp'][b, j]:.3g} {robot.unit} and "
                                                    f"{math.degrees(fields['ang'][b, j]):.3g} deg.")
            message[b, j] = f"{head}; {tail}"
    # the pitch ranges where the closed form says the pitch is out of reach (sweeps only the failed targets)
    fail_rows = np.flatnonzero(~fields["ok"].any(axis=1))
    if len(fail_rows):
        from ..numeric import shoulder_distance

        sh = shoulder_reach(robot)
        far = shoulder_distance(sh, pts[fail_rows]) > sh[-1] + tol[0]  # type: ignore[arg-type, index]
        code[fail_rows[far]] = 1
        far_rows = fail_rows[far]
        fail_rows, far = fail_rows[~far | none_valid[fail_rows]], far[~far | none_valid[fail_rows]]  # type: ignore[index]
        far = np.isin(fail_rows, far_rows)
        for b in fail_rows[far]:
            d = float(shoulder_distance(sh, pts[b:b + 1])[0])  # type: ignore[arg-type]
            message[b] = (f"unreachable: target is {d:.6g} {robot.unit} from the shoulder; the arm reaches at most "
                          f"{sh[-1]:.6g} {robot.unit} (in any direction).")  # type: ignore[index]
        near = fail_rows[~far & ~none_valid[fail_rows]]  # type: ignore[index]
        if len(near):
            q0r = q0[near].copy()
            if solver.roll:
                q0r[:, 4] = out_q[near, 0, 4]     # the roll the direction needs
            spans = reachable_pitches(robot, solver, pts[near], q0r, enforce_limits)
            for j, b in enumerate(near):
                text = pitch_range_text(spans[j])
                w = float(psi[b])
                if spans[j] == [(-math.pi, math.pi)] or not text \
                        or any(lo <= w <= hi or lo <= w + 2 * math.pi <= hi for lo, hi in spans[j]):
                    inside = code[b] != 2
                    miss = float(np.min(fields["ang"][b][inside] if inside.any() else fields["ang"][b]))
                    for k in range(4):
                        message[b, k] = (f"the direction is pitch {math.degrees(w):.4g} deg, which is reachable here, "
                                         f"but the tool's z axis misses it by {math.degrees(miss):.2g} deg at best (the "
                                         "robot file's rounding tilts the tool's z axis off the roll axis): give the "
                                         f"pitch instead (pitch= / --pitch {math.degrees(w):.4g} --deg); "
                                         f"{str(message[b, k]).split('; ', 1)[1]}")
                    continue
                hint = (f"pitch {math.degrees(psi[b]):.4g} deg is not reachable at this point; reachable pitches "
                        f"here: {text} (give the pitch with pitch= / --pitch)")
                for k in range(4):
                    message[b, k] = (f"the direction is a pitch of {math.degrees(psi[b]):.4g} deg here; {hint}; "
                                     f"{str(message[b, k]).split('; ', 1)[1]}")
    message[fields["ok"]] = ""
    dist = np.linalg.norm(out_q - q0[:, None, :], axis=-1)
    order = np.argsort(np.where(fields["ok"], 0.0, 1e9) + dist, axis=-1, kind="stable")
    take = lambda a: np.take_along_axis(a, order, axis=1)  # noqa: E731
    return IKResult(q=np.take_along_axis(out_q, order[..., None], axis=1), success=take(fields["ok"]),
                    position_error=take(fields["dp"]), rotation_error=take(fields["ang"]),
                    iterations=np.zeros((B, 4), dtype=np.int64),
                    branch=take(np.broadcast_to(_LABELS, (B, 4)).astype(object)),
                    within_limits=take(fields["within"]), reason=_REASON_TEXT[take(code)], message=take(message))
