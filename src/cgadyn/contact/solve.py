"""``solve_contacts``: the frictional contact problem (K11-K13), with one-row interval blocks
(joint limits, friction loss: K26), of given ``G``, ``g``, ``μ`` solved by ADMM (K16-K17) or
PGS (K18), one problem or a batch in one compiled call; inputs checked, statuses worded
(``docs/contact.md``)."""

from __future__ import annotations

from dataclasses import dataclass

import numba
import numpy as np

from .._threads import PARALLEL_LOCK
from ..algorithms._inputs import nonnegative
from ..algorithms.status import DELASSUS_SINGULAR, NONFINITE_INPUT, OK, decode
from . import ncp
from .admm import SCRATCH_ROWS
from .solver import ADMM, PGS, solve_batch, solve_one

SOLVERS = {"admm": ADMM, "pgs": PGS}
SYMMETRY = 1e-9
"""G is refused as not symmetric where ``|G - Gᵀ|∞ > SYMMETRY · max(1, |G|∞)``."""


@dataclass(frozen=True)
class ContactSolveInfo:
    """How the forces were found (arrays of shape (B,) for a batch): ``iterations``, the
    residuals at the returned forces (K19) ``primal`` (ADMM: ``‖x - z‖∞``, the distance of the
    linear step from the cones; PGS: 0), ``dual`` (``‖σ̃ - P_K*(σ̃)‖∞``), ``complementarity``
    (``max_i |λ_i · σ̃_i|``), ``converged`` (the stopping rule passed) and ``rho`` (ADMM's last
    penalty)."""

    iterations: int | np.ndarray
    primal: float | np.ndarray
    dual: float | np.ndarray
    complementarity: float | np.ndarray
    converged: bool | np.ndarray
    rho: float | np.ndarray


def _array(x, name: str) -> np.ndarray:
    try:
        a = np.asarray(x, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be an array of numbers, got {type(x).__name__}") from None
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name} contains NaN or inf")
    return a


def _per_row(x, name: str, batch: tuple, m: int, size: int, what: str) -> np.ndarray:
    """``x`` as a (B..., size) array: a number for all, (size,) for all problems, or one row
    per problem."""
    a = _array(x, name)
    if a.ndim == 0:
        a = np.full(size, float(a))
    if a.shape not in ((size,), batch + (size,)):
        raise ValueError(f"{name} must be a number, ({size},) ({what}) or {batch + (size,)} "
                         f"for G of shape {batch + (m, m)}, got shape {a.shape}")
    return _compiled_layout(np.broadcast_to(a, batch + (size,)))


def _compiled_layout(a: np.ndarray) -> np.ndarray:
    """``a`` as a writable C-contiguous array of float64, copied where it is not one (a
    broadcast view, a caller's read-only array): the types the contact step inside the
    rollouts hands ``solve_one``, so that one compiled specialisation of the solvers serves
    that step, single problems and batches (numba compiles them again, tens of seconds,
    for an argument that is read-only)."""
    return np.require(a, dtype=np.float64, requirements=["C", "W"])


def _settings(tolerance, relative_tolerance, max_iterations, warm: bool,
              proximal) -> np.ndarray:
    for name, value in (("tolerance", tolerance), ("relative_tolerance", relative_tolerance),
                        ("proximal", proximal)):
        nonnegative(value, name)
    if proximal <= 0:
        raise ValueError(f"proximal must be > 0 (ADMM's proximal weight η), got {proximal!r}")
    if isinstance(max_iterations, bool) or not isinstance(max_iterations, int | np.integer) \
            or max_iterations < 0:
        raise ValueError(f"max_iterations must be an integer >= 0, got {max_iterations!r}")
    s = np.zeros(ncp.SETTINGS)
    s[ncp.ABS_TOL], s[ncp.REL_TOL], s[ncp.MAX_ITER] = tolerance, relative_tolerance, \
        max_iterations
    s[ncp.WARM], s[ncp.PROX] = float(warm), proximal
    s[ncp.POWER_INIT], s[ncp.POWER_STEP], s[ncp.RATIO] = 0.2, 0.05, 10.0
    return s


def _explain(status: int, batch: bool) -> str:
    code, _, sample = decode(status)
    where = f"problem {sample}: " if batch else ""
    if code == DELASSUS_SINGULAR:
        return (f"{where}G + R + (ρ + η) I has no Cholesky factor: G is not positive "
                f"semi-definite (a Delassus matrix J M⁻¹ Jᵀ always is)")
    if code == NONFINITE_INPUT:
        return f"{where}an input holds NaN or inf"
    return f"{where}the iterations diverged (a non-finite residual)"


def solve_contacts(G, g, mu, compliance=None, solver: str = "admm", tolerance: float = 1e-10,
                   max_iterations: int = 1000, warm_start=None, relative_tolerance: float = 0.0,
                   proximal: float = 1e-6, bounds=None) -> tuple[np.ndarray, ContactSolveInfo]:
    """The contact forces ``λ`` (m,) of the NCP ``K_μ ∋ λ ⊥ σ + Γ(σ) ∈ K_μ*`` with
    ``σ = (G + R) λ + g`` (K11-K13; ``docs/contact.md``), and a ``ContactSolveInfo``.

    ``G`` (m, m) the Delassus matrix (symmetric, positive semi-definite, maybe singular),
    ``g`` (m,) the free velocity, ``m = 3 nc + nb``: each contact's rows ``(t₁, t₂, n)``
    (normal last, Pinocchio's order), then ``nb`` one-row blocks whose impulse lies in an
    interval ``bounds[b] = [lo, hi]`` (``bounds`` (nb, 2), default none; ``[0, inf]`` a joint
    limit's ``λ >= 0``, ``[-f, f]`` a friction loss, ``[-inf, inf]`` a coupling's
    unbounded row; ``-σ`` in the interval's normal cone, K26); ``mu`` a number or (nc,)
    friction coefficients >= 0;
    ``compliance`` the diagonal of ``R`` (a number, (m,)); ``solver`` ``"admm"`` (K16-K17) or
    ``"pgs"`` (K18); the stopping rule (K19) takes each residual below ``tolerance`` or below
    ``relative_tolerance`` times its scale; ``warm_start`` (m,) forces to start from (projected
    on the blocks); ``proximal`` ADMM's proximal weight ``η``. Batches: ``G`` (B, m, m), the
    others (B, ...) or shared, solved in one parallel compiled call. A problem that does not
    converge within ``max_iterations`` is returned with ``converged`` False, not raised.
    """
    if solver not in SOLVERS:
        raise ValueError(f"solver must be one of {sorted(SOLVERS)}, got {solver!r}")
    Ga = _array(G, "G")
    ba = np.zeros((0, 2)) if bounds is None else np.asarray(bounds, dtype=float)
    if ba.ndim != 2 or ba.shape[1] != 2 or np.any(np.isnan(ba)) or \
            np.any(ba[:, 0] == np.inf) or np.any(ba[:, 1] == -np.inf) \
            or np.any(ba[:, 0] > ba[:, 1]):
        raise ValueError(f"bounds must be (nb, 2) intervals [lo, hi] with lo <= hi (lo may "
                         f"be -inf, hi inf: an unbounded row), got {ba.tolist()!r}")
    nb = ba.shape[0]
    if Ga.ndim not in (2, 3) or Ga.shape[-1] != Ga.shape[-2] or Ga.shape[-1] < nb or \
            (Ga.shape[-1] - nb) % 3:
        raise ValueError(f"G must be (m, m) or (B, m, m) with m = 3 × contacts + {nb} "
                         f"interval rows, got shape {Ga.shape}")
    m = Ga.shape[-1]
    nc, batch = (m - nb) // 3, Ga.shape[:-2]
    asym = np.abs(Ga - np.swapaxes(Ga, -1, -2)).max(initial=0.0)
    if asym > SYMMETRY * max(1.0, np.abs(Ga).max(initial=0.0)):
        raise ValueError(f"G must be symmetric (a Delassus matrix J M⁻¹ Jᵀ), but |G - Gᵀ| "
                         f"reaches {asym:.3g}")
    ga = _array(g, "g")
    if ga.shape not in ((m,), batch + (m,)):
        raise ValueError(f"g must be ({m},) or {batch + (m,)} for G of shape {Ga.shape}, got "
                         f"shape {ga.shape}")
    mua = _per_row(mu, "mu", batch, m, nc, "one friction coefficient per contact")
    if np.any(mua < 0):
        raise ValueError(f"mu must be >= 0 (friction coefficients), got {np.min(mua):.6g}")
    R = _per_row(0.0 if compliance is None else compliance, "compliance", batch, m, m,
                 "the diagonal of R")
    if np.any(R < 0):
        raise ValueError(f"compliance must be >= 0, got {np.min(R):.6g}")
    lam = np.zeros(batch + (m,))
    if warm_start is not None:
        w = _array(warm_start, "warm_start")
        if w.shape not in ((m,), batch + (m,)):
            raise ValueError(f"warm_start must be ({m},) or {batch + (m,)}, got shape "
                             f"{w.shape}")
        lam[...] = w
    s = _settings(tolerance, relative_tolerance, max_iterations, warm_start is not None,
                  proximal)
    info = np.zeros(batch + (ncp.INFO,))
    Gc = _compiled_layout(Ga)
    gc = _compiled_layout(np.broadcast_to(ga, batch + (m,)))
    bc = _compiled_layout(np.broadcast_to(ba, batch + ba.shape))
    code = SOLVERS[solver]
    if batch:
        with PARALLEL_LOCK:
            status = solve_batch(code, Gc, gc, mua, bc, R, s, lam, info,
                                 numba.get_num_threads())
    else:
        status = solve_one(code, Gc, gc, mua, bc, R, s, lam, info, np.empty((m, m)),
                           np.empty((SCRATCH_ROWS, max(m, 6))))
    if status != OK:
        raise ValueError(_explain(int(status), bool(batch)))
    it = info[..., ncp.ITERATIONS].astype(np.int64)
    conv = info[..., ncp.CONVERGED] != 0.0
    pick = (lambda a: a) if batch else (lambda a: a.item())
    return lam, ContactSolveInfo(pick(it), pick(info[..., ncp.PRIMAL]),
                                 pick(info[..., ncp.DUAL]),
                                 pick(info[..., ncp.COMPLEMENTARITY]), pick(conv),
                                 pick(info[..., ncp.RHO]))
