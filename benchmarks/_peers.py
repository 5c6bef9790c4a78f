"""Build the same arm in armkit's peers, from an armkit ``Robot``'s DH table, base and tool.

Used by ``benchmarks/bench_fk.py``, ``benchmarks/bench_ik.py`` and ``tests/peers``. Each
builder returns ``None`` when its peer is not installed (install them with
``pip install -e '.[bench]'``, see ``make bench``).

Every peer gets the arm from the DH table through its *own* code, not through armkit's
compiled chain, so that agreement is evidence:

* RTB (``roboticstoolbox-python``): ``DHRobot`` from ``RevoluteDH``/``PrismaticDH`` (or
  the ``MDH`` links for the modified convention), with ``base``/``tool``; its C++ path
  is ``DHRobot.ets()`` (``ETS.eval``, ``ETS.jacob0``; ``ETS.fkine`` on a batch of rows).
* Pinocchio, pytorch_kinematics: a URDF written here from the DH rows (one revolute or
  prismatic joint per row about its local z, the constant DH transforms as joint origins,
  the base folded into the first origin, the tool as a fixed joint to a ``tool`` link).
* ikpy: the same origins as ``URDFLink`` objects.

The uniform functions of :class:`Peer` take ``q`` in radians (length units for prismatic
joints) and return NumPy arrays in armkit's conventions: ``fk(q) -> (4, 4)``,
``jacobian(q) -> (6, n)`` rows ``(v, omega)`` in the base (world) frame, ``v`` the
velocity of the tool origin.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

__all__ = ["Peer", "peers_for", "dh_origins", "urdf_text", "build_rtb", "build_pinocchio", "build_ikpy",
           "build_pytorch_kinematics"]


@dataclass
class Peer:
    """One peer's model of an arm, behind armkit's conventions."""

    name: str
    fk: Callable[[np.ndarray], np.ndarray]
    jacobian: Callable[[np.ndarray], np.ndarray] | None = None
    fk_batch: Callable[[np.ndarray], np.ndarray] | None = None  # (B, n) -> (B, 4, 4), when the peer batches
    model: Any = None


# ------------------------------------------------------------------ DH -> joint origins
def _rz(t: float) -> np.ndarray:
    c, s = math.cos(t), math.sin(t)
    return np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]])


def _rx(t: float) -> np.ndarray:
    c, s = math.cos(t), math.sin(t)
    return np.array([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1.0]])


def _trans(x: float, y: float, z: float) -> np.ndarray:
    T = np.eye(4)
    T[:3, 3] = (x, y, z)
    return T


def dh_origins(robot) -> tuple[list[np.ndarray], np.ndarray]:
    """Joint origins of the arm written as a URDF-style tree, straight from the DH table.

    Returns ``(origins, tail)``: ``origins[i]`` is the pose of joint ``i``'s frame (whose z
    axis is the joint axis, at ``q_i = 0``) in the frame of joint ``i - 1`` (in the base
    for ``i = 0``), and ``tail`` the pose of the tool in the last joint frame.

    Standard DH row ``i``: ``Rz(theta_i + q_i) Tz(d_i) Tx(a_i) Rx(alpha_i)`` (``d_i + q_i``
    for a prismatic joint); modified DH row ``i``: ``Rx(alpha_i) Tx(a_i) Rz(theta_i + q_i) Tz(d_i)``.
    """
    origins = []
    carry = np.asarray(robot.base, dtype=float)
    for j in robot.joints:
        prismatic = j.kind == "prismatic"
        if robot.convention == "standard":
            # the motion comes first; for a prismatic joint Tz(q) commutes with Rz(theta)
            before = np.eye(4) if prismatic else _rz(j.theta)
            after = _rz(j.theta) @ _trans(0, 0, j.d) if prismatic else _trans(0, 0, j.d)
            after = after @ _trans(j.a, 0, 0) @ _rx(j.alpha)
        else:
            before = _rx(j.alpha) @ _trans(j.a, 0, 0) @ _rz(j.theta) @ _trans(0, 0, j.d)
            after = np.eye(4)
        origins.append(carry @ before)
        carry = after
    return origins, carry @ np.asarray(robot.tool, dtype=float)


def _rpy(R: np.ndarray) -> tuple[float, float, float]:
    """URDF roll-pitch-yaw (R = Rz(yaw) Ry(pitch) Rx(roll))."""
    from scipy.spatial.transform import Rotation

    r, p, y = Rotation.from_matrix(R).as_euler("xyz")
    return float(r), float(p), float(y)


def urdf_text(robot) -> str:
    """The arm as URDF text: links ``link0 .. link<n>`` and ``tool``, joints ``q1 ..`` about local z."""
    origins, tail = dh_origins(robot)

    def origin(T: np.ndarray) -> str:
        xyz = " ".join(repr(float(v)) for v in T[:3, 3])
        rpy = " ".join(repr(v) for v in _rpy(T[:3, :3]))
        return f'<origin xyz="{xyz}" rpy="{rpy}"/>'

    inertial = ('<inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" '
                'izz="0.01"/></inertial>')
    lines = [f'<robot name="{robot.name}">']
    lines += [f'<link name="link{i}">{inertial}</link>' for i in range(robot.n + 1)]
    lines.append(f'<link name="tool">{inertial}</link>')
    for i, (j, T) in enumerate(zip(robot.joints, origins)):
        kind = "prismatic" if j.kind == "prismatic" else "revolute"
        lo = j.lower if math.isfinite(j.lower) else -1e6
        hi = j.upper if math.isfinite(j.upper) else 1e6
        lines.append(f'<joint name="{j.name}" type="{kind}"><parent link="link{i}"/><child link="link{i + 1}"/>'
                     f'{origin(T)}<axis xyz="0 0 1"/>'
                     f'<limit lower="{lo!r}" upper="{hi!r}" effort="100" velocity="10"/></joint>')
    lines.append(f'<joint name="tool_joint" type="fixed"><parent link="link{robot.n}"/><child link="tool"/>'
                 f'{origin(tail)}</joint>')
    lines.append("</robot>")
    return "\n".join(lines)


# ------------------------------------------------------------------------------ peers
def build_rtb(robot) -> tuple[Peer, Peer] | None:
    """``(DHRobot (Python), ETS (C++))`` peers, or None without roboticstoolbox."""
    try:
        import roboticstoolbox as rtb
        from spatialmath import SE3
    except ImportError:
        return None
    links = []
    for j in robot.joints:
        qlim = [j.lower if math.isfinite(j.lower) else -1e6, j.upper if math.isfinite(j.upper) else 1e6]
        if robot.convention == "standard":
            if j.kind == "prismatic":
                links.append(rtb.PrismaticDH(theta=j.theta, a=j.a, alpha=j.alpha, offset=j.d, qlim=qlim))
            else:
                links.append(rtb.RevoluteDH(d=j.d, a=j.a, alpha=j.alpha, offset=j.theta, qlim=qlim))
        else:
            if j.kind == "prismatic":
                links.append(rtb.PrismaticMDH(theta=j.theta, a=j.a, alpha=j.alpha, offset=j.d, qlim=qlim))
            else:
                links.append(rtb.RevoluteMDH(d=j.d, a=j.a, alpha=j.alpha, offset=j.theta, qlim=qlim))
    dh = rtb.DHRobot(links, name=robot.name, base=SE3(np.asarray(robot.base), check=False),
                     tool=SE3(np.asarray(robot.tool), check=False))
    ets = dh.ets()
    py = Peer("rtb DHRobot", fk=lambda q: dh.fkine(q).A, jacobian=lambda q: dh.jacob0(q), model=dh)

    def fk_batch(Q: np.ndarray) -> np.ndarray:  # ETS.fkine loops over the rows in C++, returns an SE3 array
        return np.asarray(ets.fkine(Q).A)

    cpp = Peer("rtb ETS (C++)", fk=ets.eval, jacobian=ets.jacob0, fk_batch=fk_batch, model=ets)
    return py, cpp


def build_pinocchio(robot) -> Peer | None:
    """Pinocchio peer (model from :func:`urdf_text`), or None without ``pin``."""
    try:
        import pinocchio as pin
    except ImportError:
        return None
    model = pin.buildModelFromXML(urdf_text(robot))
    data = model.createData()
    fid = model.getFrameId("tool")
    world_aligned = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED

    def fk(q: np.ndarray) -> np.ndarray:
        pin.forwardKinematics(model, data, q)
        return pin.updateFramePlacement(model, data, fid).homogeneous

    def jacobian(q: np.ndarray) -> np.ndarray:
        return pin.computeFrameJacobian(model, data, q, fid, world_aligned)

    return Peer("pinocchio", fk=fk, jacobian=jacobian, model=(model, data, fid))


def build_ikpy(robot) -> Peer | None:
    """ikpy peer (``URDFLink`` chain from :func:`dh_origins`), or None without ikpy."""
    try:
        from ikpy.chain import Chain
        from ikpy.link import OriginLink, URDFLink
    except ImportError:
        return None
    origins, tail = dh_origins(robot)
    links = [OriginLink()]
    for j, T in zip(robot.joints, origins):
        prismatic = j.kind == "prismatic"
        links.append(URDFLink(name=j.name, origin_translation=T[:3, 3], origin_orientation=np.array(_rpy(T[:3, :3])),
                              rotation=None if prismatic else np.array([0.0, 0.0, 1.0]),
                              translation=np.array([0.0, 0.0, 1.0]) if prismatic else None,
                              joint_type="prismatic" if prismatic else "revolute"))
    links.append(URDFLink(name="tool", origin_translation=tail[:3, 3], origin_orientation=np.array(_rpy(tail[:3, :3])),
                          joint_type="fixed"))
    mask = [False] + [True] * robot.n + [False]
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        chain = Chain(links, active_links_mask=mask, name=robot.name)
    full = np.zeros(robot.n + 2)

    def fk(q: np.ndarray) -> np.ndarray:
        full[1:-1] = q
        return chain.forward_kinematics(full)

    return Peer("ikpy", fk=fk, model=chain)


def build_pytorch_kinematics(robot) -> Peer | None:
    """pytorch_kinematics peer on CPU float64 tensors (serial chain from :func:`urdf_text`), or None."""
    try:
        import pytorch_kinematics as pk
        import torch
    except ImportError:
        return None
    previous = torch.get_default_dtype()
    torch.set_default_dtype(torch.float64)  # else the URDF origins are parsed to float32
    try:
        chain = pk.build_serial_chain_from_urdf(urdf_text(robot), "tool").to(dtype=torch.float64)
    finally:
        torch.set_default_dtype(previous)

    def fk_batch(Q: np.ndarray) -> np.ndarray:
        return chain.forward_kinematics(torch.from_numpy(Q)).get_matrix().numpy()

    def fk(q: np.ndarray) -> np.ndarray:
        return fk_batch(np.asarray(q, dtype=float)[None])[0]

    def jacobian(q: np.ndarray) -> np.ndarray:
        return chain.jacobian(torch.from_numpy(np.asarray(q, dtype=float)[None]))[0].numpy()

    return Peer("pytorch_kinematics", fk=fk, jacobian=jacobian, fk_batch=fk_batch, model=chain)


def peers_for(robot) -> list[Peer]:
    """Every installed peer's model of ``robot`` (RTB as two: Python DHRobot and C++ ETS)."""
    out: list[Peer] = []
    rtb = build_rtb(robot)
    if rtb is not None:
        out.extend(rtb)
    for build in (build_pinocchio, build_ikpy, build_pytorch_kinematics):
        peer = build(robot)
        if peer is not None:
            out.append(peer)
    return out
