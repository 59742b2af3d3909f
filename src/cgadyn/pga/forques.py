"""Forques (force + torque as one (d-1)-vector, section 2.3) acting on a body, section 2.5.7.

Every forque is a callable ``F(M, B, t) -> F_b`` returning the forque in the body frame;
conservative ones also have ``potential(M)``. ``Forques`` adds them (eq. 2.3.3, the total
forque is the sum); any user callable with the same signature may be added too.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from .inertia import Inertia
from .model import PGA

__all__ = ["Damping", "Forques", "Gravity", "Hooke", "Wrench", "forque_at"]


def forque_at(model: PGA, force, point=None, torque=None) -> np.ndarray:
    """The forque of a force f through a point q plus a pure torque: F = q ∨ (f I) + ...

    ``force`` (d,) acts along the line through ``point`` (default the origin), eq. (2.25).
    ``torque`` holds plane torques T_ij (order ``model.euclidean_planes``; in 3D
    (tau_z, -tau_y, tau_x)), each the couple of force e_j at e_i and -e_j at the origin.
    """
    q = model.origin if point is None else model.point(point)
    f = model.vee(q, model.direction(force))
    if torque is not None:
        torque = np.asarray(torque, dtype=float)
        if torque.shape != (len(model.eij),):
            raise ValueError(f"{len(model.eij)} plane torques expected for d={model.d}")
        for tij, (i, j) in zip(torque, model.euclidean_planes, strict=True):
            ei, ej = np.eye(model.d)[i - 1], np.eye(model.d)[j - 1]
            couple = model.vee(model.point(ei) - model.origin, model.direction(ej))
            f = f + tij * couple
    return f


class Gravity:
    """Gravity, eq. (2.31) generalised: F_g = I[M~ (eps g) M], a force m g through the
    centroid (the paper's ``!(~M >>> -9.81e02)`` for unit mass). ``g`` is the world-frame
    acceleration vector (d,)."""

    def __init__(self, inertia: Inertia, g):
        self.inertia = inertia
        self.g = inertia.model._check_coords(g, "gravity")
        self.rate = inertia.model.translation_rate(self.g)

    def __call__(self, m, b, t: float = 0.0) -> np.ndarray:
        model = self.inertia.model
        return self.inertia.apply(model.sandwich(model.reverse(m), self.rate))

    def potential(self, m) -> float:
        model = self.inertia.model
        c = model.coords(model.sandwich(m, model.point(self.inertia.com)))
        return float(-self.inertia.mass * self.g @ c)


class Hooke:
    """Hooke spring from body point P_b to world point A_w: F_H = k (P_b ∨ M~ A_w M)
    (section 2.5.7), a force k (a - p) through P."""

    def __init__(self, model: PGA, body_point, world_point, k: float):
        if not np.isfinite(k) or k < 0:
            raise ValueError(f"spring constant must be finite and >= 0, got {k}")
        self.model = model
        self.p = model.point(body_point)
        self.a = model.point(world_point)
        self.k = float(k)

    def __call__(self, m, b, t: float = 0.0) -> np.ndarray:
        model = self.model
        return self.k * model.vee(self.p, model.sandwich(model.reverse(m), self.a))

    def potential(self, m) -> float:
        model = self.model
        r = model.coords(model.sandwich(m, self.p)) - model.coords(self.a)
        return 0.5 * self.k * float(r @ r)


class Damping:
    """Damping F_d = *(-alpha B) (section 2.5.7): the unit inertia (Hodge dual) of -alpha B,
    so that its power B ∨ F_d = -2 alpha T_unit <= 0."""

    def __init__(self, model: PGA, alpha: float):
        if not np.isfinite(alpha) or alpha < 0:
            raise ValueError(f"damping coefficient must be finite and >= 0, got {alpha}")
        self.unit = Inertia.unit(model)
        self.alpha = float(alpha)

    def __call__(self, m, b, t: float = 0.0) -> np.ndarray:
        return self.unit.apply(-self.alpha * np.asarray(b))


class Wrench:
    """A constant applied forque given by force (at ``point``) and plane torques, fixed in
    the body frame (``frame='body'``) or in the world (``'world'``: F_b = M~ F_w M)."""

    def __init__(self, model: PGA, force, torque=None, point=None, frame: str = "body"):
        if frame not in ("body", "world"):
            raise ValueError(f"frame must be 'body' or 'world', got {frame!r}")
        self.model, self.frame = model, frame
        self.f = forque_at(model, force, point, torque)

    def __call__(self, m, b, t: float = 0.0) -> np.ndarray:
        if self.frame == "body":
            return self.f
        return self.model.sandwich(self.model.reverse(m), self.f)


class Forques:
    """The total forque F = sum of the parts (section 2.3.3); parts are any callables
    ``(M, B, t) -> F_b``. ``potential`` sums the parts that have one."""

    def __init__(self, *parts: Callable):
        for p in parts:
            if not callable(p):
                raise ValueError(f"a forque must be callable (M, B, t) -> F, got {p!r}")
        self.parts = list(parts)

    def __call__(self, m, b, t: float = 0.0) -> np.ndarray:
        total = 0.0
        for p in self.parts:
            total = total + p(m, b, t)
        return total if self.parts else np.zeros(np.shape(b))

    def potential(self, m) -> float:
        return float(sum(p.potential(m) for p in self.parts if hasattr(p, "potential")))
