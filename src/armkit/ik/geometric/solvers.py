"""Every IK solution of a 6-joint chain in closed form, by subproblem decomposition (IK-Geo style).

Each solver takes a :class:`~.poe.POE` and one target ``(R (3, 3), p (3,))`` and returns a
:class:`Solutions` ``(q (m, n), ls (m,), singular (m,))``: all solutions, each checked by
:meth:`POE.fk` to :data:`TOL` times the arm's size (position) and :data:`TOL` rad (rotation).
``ls`` is True only when the target is out of reach: then no solution passes the check and the
least-squares candidates are returned instead (``m`` may also be 0). ``singular`` marks a
solution at a singularity that leaves a family of solutions; one member is returned, with the
free joint at ``q_ref`` (0 without it). Revolute angles are in (-π, π]; a prismatic joint's
value is a length. Joints are numbered from 1 in the text below, from 0 in the code.

=================================== ==========================================================
solver                              axes (the classifier checks them; the solvers assume them)
=================================== ==========================================================
``spherical_two_intersecting``      4, 5, 6 meet; 1, 2 meet (Puma, Jaco, Stanford: joint 3 may
                                    be prismatic). SP3 (q3), SP2 (q1, q2).
``spherical_two_parallel``          4, 5, 6 meet; 2 ∥ 3. SP4 (q1), SP3 (q3), SP1 (q2).
``spherical``                       4, 5, 6 meet. 1-D search over q1 (:mod:`.search`, kind SW):
                                    q3 by SP3, the axis-2 component as residual; SP1 (q2).
``three_parallel``                  2 ∥ 3 ∥ 4. SP6 (q1, q5), SP1 (q2+q3+q4, q6), SP3 (q3), SP1 (q2).
``three_parallel_two_intersecting`` 2 ∥ 3 ∥ 4; 5, 6 meet (UR). SP4 (q1), SP4 (q5), then as above.
``spherical_base``                  1, 2, 3 meet (a spherical wrist at the base): the reversed
                                    chain (:func:`reverse`) by ``spherical_wrist``.
``two_intersecting``                5, 6 meet; no two of axes 2, 3, 4 parallel (else SP5
                                    degenerates). 1-D search over q1 (kind TI) with SP5 (q2, q3,
                                    q4) and the axis-5/6 angle as residual; SP1 (q5), SP1 (q6).
``two_parallel``                    2 ∥ 3: 1-D search over q6 (kind TP) with SP6 (q1, q4) and
                                    the distance residual; SP1 (q2, q5).
``spherical_middle``                2, 3, 4 meet: 1-D search over q6 (kind SM) with SP3 (q1) and
                                    the axis-5 component as residual; SP1 (q5), the spherical
                                    joint as a wrist (q2, q3, q4).
=================================== ==========================================================

The 1-D searches share one compiled engine (:mod:`.search`): :data:`SEARCH_N` samples over a
turn, branches followed from sample to sample, sign changes refined by false position, branch
ends and near-zero extrema searched; their resolution is stated there. Up to 16 solutions.

Every spherical-wrist solver ends with the wrist: SP2 (q4, q5) on the axis-6 direction and SP1
(q6); when axes 4 and 6 line up (``R_36 h6 ∥ h4``) q4 is set to ``q_ref[3]`` and ``singular`` set.

Before solving, :func:`align` slides the points of ``P`` along their axes so that axes that
meet share one point (and makes parallel axes exactly parallel): the solvers work on that
*ideal* chain. When the robot's axes only nearly meet or are nearly parallel, the ideal chain
differs from the true one, and each solution is polished by Newton steps on the true chain
(:func:`polish`, Jacobian from the POE) before the check.

The solver cores use only scalar math and small arrays, like :mod:`.subproblems`:
:func:`kernels` compiles them with Numba (``njit(cache=True)``, on first use: about a minute
for all of them, then loaded from Numba's disk cache in about a second). The wrappers use
them when armkit's back end is Numba (:func:`armkit.set_backend`; for ``"auto"`` once armkit's
own kernels are ready), the plain functions otherwise; ``jit=True`` / ``jit=False`` force one.

The cores live in one file per class, all importable from here: :mod:`.solvers_wrist` (the wrist,
the 3R position, the 3 x 3 helpers), :mod:`.solvers_parallel` (three parallel axes),
:mod:`.solvers_search` (the classes of the 1-D searches), :mod:`.solvers_check` (each core with
its FK check; one target, a batch, a sweep) and :mod:`.solvers_chain` (:func:`align`,
:func:`reverse`, :func:`polish`). :func:`kernels` compiles them in one namespace, the kernels of
:data:`INLINE` inline into their one caller (fewer levels of calls to compile: see there). For one target
of :func:`armkit.ik` / :func:`armkit.ik_all`, :mod:`.one_call` runs a solver and the rest of the
call in one compiled call.
"""

from __future__ import annotations

import math
import types
import weakref
from typing import Any, Callable, NamedTuple, Optional

import numpy as np
from numpy.typing import NDArray

from ... import _jit_loader, kinematics
from . import _kernels as _kk
from . import search2d as _search2d
from . import subproblems as _sp
from ._kernels import _cs_from, _fk_err_from, _fk_err_sc, _t, _tcross, _tnorm, _tsp1_abr, _tsp1_cs  # noqa: F401
# (in the kernels' namespace; the SP1 and vector helpers inlined)
from .poe import POE
from .search import MAXROOT, SM, SW, TI, TP, _search  # noqa: F401  (in the kernels' namespace)
from .search import N as _SEARCH_N
from .search import kernels as _search_kernels
from .solvers_chain import _jacobian, _log_vec, _points, _size, align, polish, reverse  # noqa: F401
from .solvers_check import (CORE_M, CORE_T, CORE_V, CORE_V_PARALLEL, EMPTY_RETRY, RETRIES, SHARP,  # noqa: F401
                            _SPH_MID, _SPHERICAL, _THREE_PARALLEL, _TI_END, _TWO_PAR, _apart, _check, _close,
                            _close_wrapped, _core_in, _closed_core, _copy_row, _distinct, _gate, _merged, _newton_from,
                            _paired, _polish_wanted, _promote, _put_passing, _repeats, _searched_core, _sharpen, _solve,
                            _solve_searched, _solve_spherical, _solve_spherical_middle, _solve_three_parallel,
                            _solve_two_intersecting_end, _solve_two_parallel, _sweep, _within_reach)
from .solvers_parallel import (PAIR_LANES, _core_three_parallel, _pair_q2, _pairs_lanes, _pairs_sp6,  # noqa: F401
                               _put_branch, _singular_wrist)
from .solvers_search import (_core_spherical_middle, _core_two_intersecting_end, _core_two_parallel,  # noqa: F401
                             _target_rows)
from .solvers_wrist import (NEAR_TANGENT, SING, WRIST_LANES, _core_spherical, _mm, _mm_to, _mtm, _mtm_to,  # noqa: F401
                            _mtv, _mtv_to, _mv, _mv_to, _perp, _perp_to, _pos_general, _pos_search,
                            _pos_two_intersecting, _pos_two_parallel, _rot_to, _rotm_to, _turn_to, _SP_TINY, _SP_TOL,
                            _sp1s, _sp1s_cs, _sp2s, _sp2cs, _sp2cs_abr, _sp2cs_disc, _sp2cs_one, _put_position, _wrist,
                            _wrist_from, _wrist_half, _wrist_lanes, _wrist_sp2)
from .subproblems import _cross, _dot, _lin, _norm, _wrap, rot, rotm, sp1, sp2, sp3, sp4, sp5, sp6  # noqa: F401

__all__ = ["Solutions", "solve_batch", "align", "reverse", "polish", "spherical_two_intersecting", "spherical_two_parallel",
           "spherical", "spherical_wrist", "three_parallel", "three_parallel_two_intersecting", "spherical_base",
           "two_intersecting", "two_parallel", "spherical_middle",
           "SOLVERS", "TOL", "SEARCH_N", "kernels"]

Array = NDArray[np.float64]

TOL = 1e-9
"""Check of every returned solution: position error ≤ TOL × arm size, rotation error ≤ TOL rad."""
SEARCH_N = _SEARCH_N
"""Samples of the searched joint over one turn in the 1-D searches (:data:`.search.N`)."""
MAXSOL = 32


class Solutions(NamedTuple):
    """All solutions ``q (m, n)``; ``ls (m,)``: least-squares candidates of an unreachable target;
    ``singular (m,)``: one member of a family of solutions (the free joint at ``q_ref``)."""
    q: Array
    ls: NDArray[np.bool_]
    singular: NDArray[np.bool_]


# ---------------------------------------------------------------------------------- wrappers
KERNELS = ("_mv", "_mtv", "_mm", "_mtm", "_perp", "_rotm_to", "_rot_to", "_mm_to", "_mtm_to", "_mv_to", "_mtv_to",
           "_perp_to", "_turn_to", "_sp1s", "_sp1s_cs", "_sp2s", "_sp2cs_disc", "_sp2cs_abr", "_sp2cs_one", "_sp2cs",
           "_wrist", "_wrist_from", "_wrist_sp2", "_wrist_half", "_wrist_lanes", "_pos_two_intersecting",
           "_pos_two_parallel", "_pos_search", "_pos_general",
           "_core_spherical", "_pairs_sp6", "_singular_wrist", "_pair_q2", "_pairs_lanes", "_put_branch",
           "_core_three_parallel", "_close", "_repeats", "_put_passing", "_merged", "_newton_from", "_copy_row",
           "_promote", "_sharpen", "_check", "_core_in", "_closed_core", "_solve_spherical",
           "_solve_three_parallel", "_distinct", "_gate", "_target_rows", "_core_two_intersecting_end",
           "_core_two_parallel", "_core_spherical_middle", "_paired", "_searched_core", "_within_reach",
           "_solve_searched", "_solve_two_intersecting_end", "_solve_two_parallel", "_solve_spherical_middle", "_solve",
           "_sweep", "_polish_wanted", "_close_wrapped", "_apart")
UNCOUNTED = ("_sp2s", "_wrist", "_wrist_from", "_wrist_sp2", "_pos_two_intersecting", "_pos_two_parallel",
             "_core_spherical", "_core_three_parallel", "_core_in", "_distinct", "_apart")
"""Kernels compiled without Numba's reference counts (:func:`.subproblems.jit_namespace`): they make no array in
their whole call tree. The spherical core calls the wrist up to four times a target, each call the small helpers
~10 times with 2-8 arrays each, and every array passed or sliced was counted up and down with an atomic
instruction: the wrist took 0.40 µs a call, 0.29 without the counts (the Kinova's wrist, a loop of 300 targets),
0.21 with its 3 x 3 helpers and SP1 inlined (:data:`INLINE`: code inlined into a function compiled without counts
has none either); its position parts the same way; the spherical core itself (its work arrays made by
``_closed_core``) 1.66 -> 1.49 µs a target."""
VECTOR = ("_core_spherical", "_core_three_parallel")
"""Kernels compiled with NumPy's error model (:func:`.subproblems.jit_namespace`): a division by zero does not raise,
so the loops of their lanes (:func:`.solvers_wrist._wrist_lanes`, :func:`.solvers_parallel._pairs_lanes`, inlined
there) compile to vector instructions; with Python's model the wrists' loop stayed scalar (four wrists 0.41 µs,
against 0.17 with it, 2026-12-07)."""
INLINE = ("_fk_err_sc", "_pos_search",
          "_core_two_intersecting_end", "_core_two_parallel", "_core_spherical_middle", "_searched_core", "_solve",
          "_mv_to", "_mtv_to", "_mm_to", "_mtm_to", "_rotm_to", "_rot_to", "_turn_to", "_perp_to",
          "_sp1s", "_sp1s_cs", "_close_wrapped", "_sp2cs", "_sp2cs_disc", "_sp2cs_abr", "_sp2cs_one", "_tsp1_abr",
          "_t", "_cs_from", "_tsp1_cs", "_put_position", "_wrist_half", "_wrist_lanes", "_pair_q2", "_pairs_lanes",
          "_put_branch", "_tcross", "_tnorm")
"""Kernels with one caller each (the FK of the candidates in ``_check``, a searched core in its ``_solve_*``, a
closed-form one in ``_closed_core``, the 3R position in the spherical core, the dispatch in the batch loops):
compiled inline into that caller (Numba's ``inline="always"``), not as functions of their own. Numba links a
called kernel's whole compiled code into its caller and optimises and compiles it there again, so every level of
calls between a kernel and its entry points repeats that work; inlining these removes a level; in ``_check``, the
call of each of up to 32 candidates with its twelve arrays too (the Kinova's core and check: 4.0 -> 3.8 µs)
(same operations, same results). The 3 x 3 helpers and SP1 have many callers, but each is a few lines: inlined,
the compiler keeps their rows in registers between them (the Kinova's wrist 0.29 -> 0.21 µs a call; the solvers'
first compile ~20 s longer)."""
_PARTS = ("solvers", "solvers_wrist", "solvers_parallel", "solvers_search", "solvers_check")
SOURCES = tuple(f"ik/geometric/{name}.py" for name in _PARTS + ("subproblems", "search", "search2d", "_kernels")) + (
    "kinematics/_jit.py",)
"""The files whose functions the compiled solver cores contain (relative to the package): a change to any of
them makes the cached copies compile anew."""
_KERNELS: Optional[types.SimpleNamespace] = None
_NO_NUMBA = False


def kernels() -> Optional[types.SimpleNamespace]:
    """The compiled solver cores (and subproblems), or None without Numba; compiled on first use."""
    global _KERNELS, _NO_NUMBA
    if _KERNELS is None and not _NO_NUMBA:
        sk = _sp.kernels()
        ek = _search_kernels()
        if sk is None or ek is None:
            _NO_NUMBA = True
            return None
        extra = _kk.extra()                 # the shared helpers (_fk_err_from), then the subproblems
        extra.update({name: sk.namespace[name] for name in _sp.KERNELS})
        extra["_search"] = ek._search
        from . import search2d

        s2 = search2d.kernels()
        if s2 is None:
            _NO_NUMBA = True
            return None
        extra["_twins"] = s2._twins   # the odd-count step of the 1-D searches (solvers_check._paired)
        extra["_newton"] = s2._newton   # failing candidates and rough solutions (_promote, _sharpen)
        ns = _sp.jit_namespace(globals(), KERNELS, extra=extra, uncounted=UNCOUNTED, vector=VECTOR)
        from numba import njit

        for name in INLINE:     # the same copies, compiled inline into their callers (they share ns as globals)
            f = globals()[name]
            ns[name] = njit(cache=True, inline="always")(types.FunctionType(f.__code__, ns, f.__name__, f.__defaults__,
                                                                             f.__closure__))

        for stem in _PARTS:     # each file's cached copies follow every file they call into
            _jit_loader.forget_stale_cache(dict(ns, __file__=ns["__file__"].replace("solvers.py", stem + ".py")),
                                           SOURCES)
        _KERNELS = types.SimpleNamespace(**{name: ns[name] for name in KERNELS})
    return _KERNELS


def _use_jit(jit: Optional[bool]) -> bool:
    """``jit`` if given, else armkit's back end (:func:`armkit.set_backend`): the compiled cores when the
    Numba back end serves (for ``"auto"``: once armkit's kernels are ready), the plain functions otherwise."""
    if jit is not None:
        return jit

    return kinematics._jit_module() is not None


class _Prepared(NamedTuple):
    solve: str          # the kernel
    kind: int           # its case
    Hi: Array           # the ideal chain
    Pi: Array
    RnT: Array
    prism: NDArray[np.bool_]
    Ht: Array           # the true chain
    Pt: Array
    exact: bool         # ideal == true (up to rounding)
    scale: float        # arm size
    reach: float        # how far off a failed candidate is still polished (polish_reach of the chains' deviation)


_PREPARED: dict[tuple[int, str], tuple[Any, Any]] = {}
_CASES = {  # name: (kernel, case, meeting axes, parallel axes, joints that may be prismatic)
    "spherical_two_intersecting": ("_solve_spherical", 0, ((0, 1), (3, 4, 5)), (), (2,)),
    "spherical_two_parallel": ("_solve_spherical", 1, ((3, 4, 5),), ((1, 2),), ()),
    "spherical": ("_solve_spherical", 2, ((3, 4, 5),), (), ()),
    "three_parallel": ("_solve_three_parallel", 3, (), ((1, 2, 3),), ()),
    "three_parallel_two_intersecting": ("_solve_three_parallel", 4, ((4, 5),), ((1, 2, 3),), ()),
    "two_intersecting": ("_solve_two_intersecting_end", 5, ((4, 5),), (), ()),
    "two_parallel": ("_solve_two_parallel", 6, (), ((1, 2),), ()),
    "spherical_middle": ("_solve_spherical_middle", 7, ((1, 2, 3),), (), ()),
}


def _cached(form: POE, key: str, make: Callable[[], Any]) -> Any:
    """``make()``, remembered for this POE object (by identity, while it lives)."""
    hit = _PREPARED.get((id(form), key))
    if hit is not None and hit[0]() is form:
        return hit[1]
    value = make()
    if len(_PREPARED) > 512:
        _PREPARED.clear()
    _PREPARED[(id(form), key)] = (weakref.ref(form), value)
    return value


def _prepare(form: POE, name: str) -> _Prepared:
    def make() -> _Prepared:
        solve, kind, meet, parallel, may_slide = _CASES[name]
        if form.n != 6:
            raise ValueError(f"{name}: for 6-joint chains, got {form.n} joints")
        bad = [k + 1 for k in range(6) if form.prismatic[k] and k not in may_slide]
        if bad:
            raise ValueError(f"{name}: joint(s) {bad} may not be prismatic here")
        if name == "two_intersecting" and (_parallel(form, 1, 2, 1e-6) or _parallel(form, 2, 3, 1e-6)):
            raise ValueError("two_intersecting: axes 2 ∥ 3 or 3 ∥ 4 make its SP5 degenerate; the solvers of "
                             "spherical wrists or three parallel axes answer such arms")
        if name == "two_parallel" and not _parallel(form, 1, 2, 1e-6):
            raise ValueError("two_parallel: axes 2 and 3 must be parallel")
        if name == "spherical_middle" and not (_meets(form, 1, 2, 1e-6) and _meets(form, 2, 3, 1e-6)):
            raise ValueError("spherical_middle: axes 2, 3 and 4 must meet in a point")
        ideal, dev = align(form, meet, parallel)
        # writable C-contiguous copies: the POE's own arrays may be read-only, and the compiled kernels would then
        # be compiled a second time for read-only arrays (the 7-joint sweep of .locked passes writable ones)
        def c(x: Any, dtype: Any = float) -> Any:
            return np.array(x, dtype=dtype, order="C")
        return _Prepared(solve, kind, c(ideal.H), c(ideal.P), c(form.R_nT), c(form.prismatic, np.bool_), c(form.H),
                         c(form.P), dev < 1e-13, _size(form), polish_reach(dev))
    return _cached(form, name, make)


def _run(name: str, form: POE, R: Array, p: Array, q_ref: Optional[Array], jit: Optional[bool]) -> Solutions:
    prep = _prepare(form, name)
    n = 6
    R = np.ascontiguousarray(R, dtype=float)
    p = np.ascontiguousarray(p, dtype=float)
    qref = _ZERO6 if q_ref is None else np.ascontiguousarray(q_ref, dtype=float)
    Q = np.zeros((MAXSOL, n))
    LS = np.zeros(MAXSOL, dtype=np.bool_)
    SG = np.zeros(MAXSOL, dtype=np.bool_)
    ST = np.zeros(MAXSOL, dtype=np.int64)
    K = kernels() if _use_jit(jit) else None
    fn = getattr(K, prep.solve) if K is not None else globals()[prep.solve]
    tol_p = TOL * prep.scale
    ng, nf = fn(prep.kind, prep.Hi, prep.Pi, prep.RnT, prep.prism, prep.Ht, prep.Pt, R, p, qref, SEARCH_N, tol_p,
                TOL, Q, LS, SG, ST)
    if nf and not (prep.exact and LS[ng:ng + nf].all()):
        # polish what the ideal chain got nearly right (nearly meeting / parallel axes, rounding); not a candidate
        # farther from the target on the true chain than the chains' difference explains (polish_reach), by the
        # test the one-call and batched kernels decide by
        wanted = K._polish_wanted if K is not None else _polish_wanted
        for i in range(ng, ng + nf):
            if not wanted(prep.Ht, prep.Pt, prep.RnT, prep.prism, R, p, Q, LS, i, 1, prep.exact,
                          prep.reach * prep.scale, prep.reach):
                continue
            qi = polish(form, Q[i], R, p)
            Rq, pq = form.fk(qi)
            if np.linalg.norm(pq - p) <= tol_p and np.linalg.norm(Rq - R) / math.sqrt(2.0) <= TOL:
                qi = np.where(form.prismatic, qi, (qi + math.pi) % (2 * math.pi) - math.pi)
                if not any(_same(qi, Q[j], form.prismatic) for j in range(ng)):
                    Q[ng] = qi
                    SG[ng] = SG[i]
                    ng += 1
    if ng:
        return Solutions(Q[:ng].copy(), np.zeros(ng, dtype=bool), SG[:ng].copy())
    return Solutions(Q[:nf].copy(), np.ones(nf, dtype=bool), SG[:nf].copy())


POLISH_WITHIN = 1e-6
"""The least FK error on the true chain (times the arm's size in position, in rad in rotation) beyond which a
candidate that failed the check is not polished (:func:`polish_reach`)."""


def polish_reach(dev: float) -> float:
    """How far from the target (as :data:`POLISH_WITHIN`) a failed candidate of an ideal chain ``dev`` away from the
    true one (:func:`.solvers_chain.align`) may be and still be polished into a solution: ``max(POLISH_WITHIN,
    1000 dev)``.

    The ideal chain's exact solutions miss the target on the true chain by about ``2 n dev`` (each of the n joints'
    axis moved by up to ``dev`` rad, its point by ``dev`` times the arm's size), and a target the true chain reaches
    lies that close to the ideal chain's reach. A candidate farther off is the closest point of a target out of
    reach (a least-squares candidate): Newton's steps cannot make it a solution, and polishing each of an
    unreachable target's eight candidates (eight least-squares steps in NumPy) took the Kinova's ``ik_all`` 7 ms,
    ``ik`` 14 ms, where a reachable target takes 10 µs (its URDF's wrist axes meet to 2e-13, so it is not exact)."""
    return max(POLISH_WITHIN, 1000.0 * dev)


_ZERO6 = np.zeros(6)
_WHICH = {"_solve_spherical": 0, "_solve_three_parallel": 1, "_solve_two_intersecting_end": 2, "_solve_two_parallel": 3,
          "_solve_spherical_middle": 4}


def case_of(name: str, form: POE) -> str:
    """The solver that answers ``name``'s class on ``form``: a spherical wrist resolves to its case (cached per
    form); a name in :data:`_CASES` has a compiled batch kernel."""
    if name == "spherical_wrist":
        return _cached(form, "wrist case", lambda: _wrist_case(form))
    return name


def solve_batch(name: str, form: POE, R: Array, p: Array, q_ref: Array, *, jit: Optional[bool] = None
                ) -> list[Solutions]:
    """:data:`SOLVERS` ``[name]`` on every target of ``R (B, 3, 3)``, ``p (B, 3)``, ``q_ref (B, n)``, the
    kernel looping over the batch in one compiled call (each target as :func:`_run` would solve it; a target
    whose candidates need the Python polish goes through :func:`_run`)."""
    name = case_of(name, form)
    if name not in _CASES:
        return [SOLVERS[name](form, R[b], p[b], q_ref[b], jit=jit) for b in range(len(R))]
    prep = _prepare(form, name)
    B, n = len(R), 6
    K = kernels() if jit is not False else None
    if K is None:
        return [_run(name, form, R[b], p[b], q_ref[b], jit) for b in range(B)]
    Q = np.zeros((1, B, MAXSOL, n))
    LS = np.zeros((1, B, MAXSOL), dtype=np.bool_)
    SG = np.zeros((1, B, MAXSOL), dtype=np.bool_)
    ST = np.zeros((1, B, MAXSOL), dtype=np.int64)
    NG = np.zeros((1, B), dtype=np.int64)
    NF = np.zeros((1, B), dtype=np.int64)
    c = np.ascontiguousarray
    # the sweep over one chain: one compiled kernel serves this and the 7-joint sweep of .locked
    K._sweep(_WHICH[prep.solve], prep.kind, prep.Hi[None], prep.Pi[None], prep.RnT[None], prep.prism, prep.Ht[None],
             prep.Pt[None], c(R, dtype=float), c(p, dtype=float), c(q_ref, dtype=float), SEARCH_N,
             np.array([TOL * prep.scale]), TOL, Q, LS, SG, ST, NG, NF)
    Q, LS, SG, NG, NF = Q[0], LS[0], SG[0], NG[0], NF[0]
    out: list[Solutions] = []
    R, p = c(R, dtype=float), c(p, dtype=float)
    for b in range(B):
        ng, nf = int(NG[b]), int(NF[b])
        if nf and not (prep.exact and LS[b, ng:ng + nf].all()) and K._polish_wanted(
                prep.Ht, prep.Pt, prep.RnT, prep.prism, R[b], p[b], Q[b], LS[b], ng, nf, prep.exact,
                prep.reach * prep.scale, prep.reach):
            out.append(_run(name, form, R[b], p[b], q_ref[b], jit))     # the rare polish: as one call
        elif ng:
            out.append(Solutions(Q[b, :ng], np.zeros(ng, dtype=bool), SG[b, :ng]))
        else:
            out.append(Solutions(Q[b, :nf], np.ones(nf, dtype=bool), SG[b, :nf]))
    return out


def _same(a: Array, b: Array, prismatic: NDArray[np.bool_]) -> bool:
    d = np.abs(a - b)
    d = np.where(prismatic, d, np.minimum(d % (2 * math.pi), 2 * math.pi - d % (2 * math.pi)))
    return bool(d.max() < 1e-8)


def spherical_two_intersecting(form: POE, R: Array, p: Array, q_ref: Optional[Array] = None, *,
                               jit: Optional[bool] = None) -> Solutions:
    """Axes 4, 5, 6 meet and axes 1, 2 meet (joint 3 revolute or prismatic): up to 8 solutions."""
    return _run("spherical_two_intersecting", form, R, p, q_ref, jit)


def spherical_two_parallel(form: POE, R: Array, p: Array, q_ref: Optional[Array] = None, *,
                           jit: Optional[bool] = None) -> Solutions:
    """Axes 4, 5, 6 meet and axes 2 ∥ 3 (all revolute): up to 8 solutions."""
    return _run("spherical_two_parallel", form, R, p, q_ref, jit)


def spherical(form: POE, R: Array, p: Array, q_ref: Optional[Array] = None, *,
              jit: Optional[bool] = None) -> Solutions:
    """Axes 4, 5, 6 meet, nothing else assumed (all revolute): closed form, up to 8 solutions.

    The wrist centre's position fixes q1, q2, q3 by SP5 (a quartic, up to 4), then the wrist gives 2 each.
    Where axes 1 ∥ 2 SP5 does not apply and the 1-D search SW of :mod:`.search` over q1 answers
    (:data:`SEARCH_N` samples a turn; SP3 for q3, the residual along axis 2). Every solution is checked by FK."""
    return _run("spherical", form, R, p, q_ref, jit)


def _meets(form: POE, i: int, j: int, tol: float = 1e-9) -> bool:
    hi, hj = form.H[i], form.H[j]
    c = np.cross(hi, hj)
    s = np.linalg.norm(c)
    pts = _points(np.asarray(form.P, dtype=float))
    if s < 1e-9:
        return False
    return abs(float((pts[j] - pts[i]) @ c)) / s <= tol * _size(form)


def _parallel(form: POE, i: int, j: int, tol: float = 1e-9) -> bool:
    return float(np.linalg.norm(np.cross(form.H[i], form.H[j]))) <= tol


def _wrist_case(form: POE) -> str:
    if _meets(form, 0, 1):
        return "spherical_two_intersecting"
    if _parallel(form, 1, 2) and not np.any(form.prismatic):
        return "spherical_two_parallel"
    return "spherical"


def spherical_wrist(form: POE, R: Array, p: Array, q_ref: Optional[Array] = None, *,
                    jit: Optional[bool] = None) -> Solutions:
    """Axes 4, 5, 6 meet: :func:`spherical_two_intersecting` when axes 1, 2 meet,
    :func:`spherical_two_parallel` when 2 ∥ 3, :func:`spherical` otherwise."""
    return _run(case_of("spherical_wrist", form), form, R, p, q_ref, jit)


def three_parallel(form: POE, R: Array, p: Array, q_ref: Optional[Array] = None, *,
                   jit: Optional[bool] = None) -> Solutions:
    """Axes 2 ∥ 3 ∥ 4 (all revolute): SP6 for q1, q5; up to 8 solutions."""
    return _run("three_parallel", form, R, p, q_ref, jit)


def three_parallel_two_intersecting(form: POE, R: Array, p: Array, q_ref: Optional[Array] = None, *,
                                    jit: Optional[bool] = None) -> Solutions:
    """Axes 2 ∥ 3 ∥ 4 and axes 5, 6 meet (UR arms; all revolute): up to 8 solutions."""
    return _run("three_parallel_two_intersecting", form, R, p, q_ref, jit)


def two_intersecting(form: POE, R: Array, p: Array, q_ref: Optional[Array] = None, *,
                     jit: Optional[bool] = None) -> Solutions:
    """Axes 5 and 6 meet (all revolute; no two of axes 2, 3, 4 parallel): up to 16 solutions.

    The 1-D search TI of :mod:`.search` over q1 (:data:`SEARCH_N` samples a turn; its resolution is
    stated there): at each q1, SP5 gives up to 4 (q2, q3, q4) that put the axis-5/6 point in place,
    and the residual of each is the angle condition of axes 5 and 6 (``(R_04 h5)ᵀ R_06 h6 = h5ᵀ h6``);
    then q5, q6 by SP1. Every solution is checked by FK."""
    return _run("two_intersecting", form, R, p, q_ref, jit)


def spherical_base(form: POE, R: Array, p: Array, q_ref: Optional[Array] = None, *,
                   jit: Optional[bool] = None) -> Solutions:
    """Axes 1, 2, 3 meet (a spherical wrist at the base): :func:`spherical_wrist` on the reversed
    chain (:func:`reverse`) for the inverse target, solutions turned back."""
    rev = _cached(form, "reversed", lambda: reverse(form))
    R = np.asarray(R, dtype=float)
    p = np.asarray(p, dtype=float)
    qr = None if q_ref is None else np.asarray(q_ref, dtype=float)[::-1]
    sol = spherical_wrist(rev, R.T, -(R.T @ p), qr, jit=jit)
    return Solutions(np.ascontiguousarray(sol.q[:, ::-1]), sol.ls, sol.singular)


def two_parallel(form: POE, R: Array, p: Array, q_ref: Optional[Array] = None, *,
                 jit: Optional[bool] = None) -> Solutions:
    """Axes 2 ∥ 3 and no other relation (all revolute): up to 16 solutions.

    The 1-D search TP of :mod:`.search` over q6 (:data:`SEARCH_N` samples, its resolution there): at each
    q6, SP6 gives up to 4 ``(q1, q4)`` from the two equations along axis 2 (position and orientation), SP1
    the sum ``θ = q2 ± q3``, and the residual is ``|d| − |P3|``; then q2, q5 by SP1."""
    return _run("two_parallel", form, R, p, q_ref, jit)


def spherical_middle(form: POE, R: Array, p: Array, q_ref: Optional[Array] = None, *,
                     jit: Optional[bool] = None) -> Solutions:
    """Axes 2, 3, 4 meet in a point (a spherical joint in the middle; all revolute): up to 16 solutions.

    The 1-D search SM of :mod:`.search` over q6 (:data:`SEARCH_N` samples): at each q6 the point of axis 5
    is at a fixed distance from the centre of the spherical joint (SP3 for q1, up to 2 branches) and its
    component along axis 5 is the residual; then q5 by SP1 and q2, q3, q4 as a wrist (SP2, SP1; at the
    wrist's singularity q2 at ``q_ref``)."""
    return _run("spherical_middle", form, R, p, q_ref, jit)


SOLVERS: dict[str, Callable[..., Solutions]] = {
    "spherical_two_intersecting": spherical_two_intersecting,
    "spherical_two_parallel": spherical_two_parallel,
    "spherical": spherical,
    "spherical_wrist": spherical_wrist,
    "three_parallel": three_parallel,
    "three_parallel_two_intersecting": three_parallel_two_intersecting,
    "spherical_base": spherical_base,
    "two_intersecting": two_intersecting,
    "two_parallel": two_parallel,
    "spherical_middle": spherical_middle,
    "gen_six_dof": _search2d.gen_six_dof,      # the general 6R: 2-D search (search2d.py)
}
"""The solvers by name (IK-Geo's names where it has them)."""
