"""The PGA inertia map I[B] as a duality (Dorst & De Keninck, sections 2.2.3-2.2.6).

The inertia map takes a rate bivector B to a momentum (d-1)-vector P = I[B]. It is stored as
a matrix from the bivector coefficients of B to the (d-1)-vector coefficients of P, so the
same class holds the eigenbasis form eq. (2.22) (a weighted complement, diagonal) and the
general form eq. (2.13) of a mass distribution in any body frame (not necessarily centroidal
or principal). With the right complement ``*`` of ``PGA.dual`` the eigenbasis form is

    I[B] = sum_k lambda_k [B]_k * e_k,   lambda = i_ij on e_ij, m on e_0i      (2.22)

which equals the point-mass sum eq. (2.13), I[B] = sum_i m_i X_i ∨ (X_i × B), with a plus
sign in every dimension, and makes the kinetic energy ½ B ∨ I[B] positive
(``tests/test_pga_inertia.py`` checks both).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .model import PGA

__all__ = ["Inertia"]


def _positive(name: str, values, expected: str) -> np.ndarray:
    values = np.asarray(values, dtype=float)
    if not np.all(np.isfinite(values)) or np.any(values <= 0):
        raise ValueError(f"{name} must be finite and positive ({expected}), got {values}")
    return values


@dataclass(frozen=True)
class Inertia:
    """A body inertia map I_b[] in the body frame.

    ``matrix[a, b]`` is the coefficient of blade ``model.dual_bivectors[a]`` in I[e_b] for
    ``e_b = model.bivectors[b]``. ``mass`` is the total mass, ``com`` the centroid in body
    coordinates (used by gravity's potential energy).
    """

    model: PGA
    matrix: np.ndarray
    mass: float
    com: np.ndarray
    inverse_matrix: np.ndarray = field(init=False, repr=False)

    def __post_init__(self):
        m = self.model
        if self.matrix.shape != (len(m.bivectors), len(m.bivectors)):
            raise ValueError(f"inertia matrix must be square of size {len(m.bivectors)}")
        # The energy form B ∨ I[B] must be positive definite (section 2.7.2).
        eye = np.zeros((len(m.bivectors), m.n))
        eye[np.arange(len(m.bivectors)), m.bivectors] = 1.0
        gram = m.vee(eye[:, None, :], self.apply(eye)[None, :, :])[..., 0]
        gram = 0.5 * (gram + gram.T)
        if not np.all(np.linalg.eigvalsh(gram) > 0):
            raise ValueError(
                "inertia map is not positive definite (B ∨ I[B] > 0 expected for every "
                "rate B): check that mass and moments are positive"
            )
        object.__setattr__(self, "inverse_matrix", np.linalg.inv(self.matrix))

    # --- the map and its inverse (eqs. 2.20, 2.21) -----------------------------------

    def apply(self, b) -> np.ndarray:
        """P = I[B]: bivector -> (d-1)-vector (momentum, eq. 2.12)."""
        b = np.asarray(b, dtype=float)
        out = np.zeros(b.shape)
        out[..., self.model.dual_bivectors] = b[..., self.model.bivectors] @ self.matrix.T
        return out

    __call__ = apply

    def inverse(self, p) -> np.ndarray:
        """B = I^-1[P]: (d-1)-vector -> bivector (eq. 2.21)."""
        p = np.asarray(p, dtype=float)
        out = np.zeros(p.shape)
        out[..., self.model.bivectors] = p[..., self.model.dual_bivectors] @ self.inverse_matrix.T
        return out

    # --- constructors -----------------------------------------------------------------

    @classmethod
    def principal(cls, model: PGA, mass: float, moments=()) -> Inertia:
        """Eigenbasis form eq. (2.22): mass m on every e_0i, moment i_ij on every e_ij.

        ``moments`` are the principal moments i_ij of the planes ``model.euclidean_planes``
        (e12, e13, ... ; in 3D that is (I_zz, I_yy, I_xx) of the classical axes), at the
        centroid, which is the body origin.
        """
        mass = float(_positive("mass", mass, "a mass > 0"))
        moments = np.asarray(moments, dtype=float).reshape(-1)
        if moments.shape != (len(model.eij),):
            raise ValueError(
                f"{len(model.eij)} principal moments expected for d={model.d} "
                f"(planes {model.euclidean_planes}), got {moments.shape[0]}"
            )
        if moments.size:
            _positive("principal moments", moments, "every moment i_ij > 0")
        lam = np.zeros(model.n)
        lam[model.e0i] = mass
        lam[model.eij] = moments
        # *e_k = sign_k e_index_k (right complement): a diagonal map up to the reindexing.
        sign, index = model._comp_sign, model._comp_index
        row = {int(k): a for a, k in enumerate(model.dual_bivectors)}
        matrix = np.zeros((len(model.bivectors), len(model.bivectors)))
        for b, k in enumerate(model.bivectors):
            matrix[row[int(index[k])], b] = lam[k] * sign[k]
        return cls(model, matrix, mass, np.zeros(model.d))

    @classmethod
    def unit(cls, model: PGA) -> Inertia:
        """Unit mass and moments: the inertia map is the complement (Hodge) dual (2.2.6)."""
        return cls.principal(model, 1.0, np.ones(len(model.eij)))

    @classmethod
    def hypercube(cls, model: PGA, mass: float, edges=None) -> Inertia:
        """Solid box with edge lengths a_k (default 1): i_ij = m (a_i^2 + a_j^2) / 12
        (the cuboid of section 2.5.8, in d dimensions)."""
        edges = np.ones(model.d) if edges is None else np.asarray(edges, dtype=float)
        if edges.shape != (model.d,):
            raise ValueError(f"{model.d} edge lengths expected for d={model.d}, got {edges}")
        _positive("edge lengths", edges, "every edge > 0")
        mass = float(_positive("mass", mass, "a mass > 0"))
        moments = [mass * (edges[i - 1] ** 2 + edges[j - 1] ** 2) / 12.0
                   for i, j in model.euclidean_planes]
        return cls.principal(model, mass, moments)

    @classmethod
    def from_moments(cls, model: PGA, mass: float, com, second_moment) -> Inertia:
        """Eq. (2.13) for a mass distribution given by its moments about the body origin.

        I[B] = ∫ X ∨ (X × B) dm with X = O + r I is quadratic in r, so it depends only on the
        mass m, the first moment m c and the second moment S = ∫ r r^T dm (d x d, about the
        body origin), whatever the frame.
        """
        mass = float(_positive("mass", mass, "a mass > 0"))
        com = model._check_coords(com, "centre of mass")
        s = np.asarray(second_moment, dtype=float)
        if s.shape != (model.d, model.d) or not np.all(np.isfinite(s)):
            raise ValueError(f"second moment must be a finite {model.d}x{model.d} matrix")
        nb = len(model.bivectors)
        basis = np.zeros((nb, model.n))
        basis[np.arange(nb), model.bivectors] = 1.0
        o = model.origin
        e = model.direction(np.eye(model.d))  # (d, n): ideal points of e_1..e_d

        def k(x, y):  # x ∨ (y × B) for every basis bivector B: (nb, n)
            return model.vee(x, model.commutator(y, basis))

        p = mass * k(o, o)
        for a in range(model.d):
            p = p + mass * com[a] * (k(o, e[a]) + k(e[a], o))
            for b in range(model.d):
                if s[a, b]:
                    p = p + s[a, b] * k(e[a], e[b])
        matrix = p[:, model.dual_bivectors].T
        return cls(model, matrix, mass, com)

    @classmethod
    def from_tensor(cls, model: PGA, mass: float, com, inertia) -> Inertia:
        """3D only: from the classical inertia tensor about the centroid (as Pinocchio's
        ``pin.Inertia(mass, lever, I)``), with the centroid at ``com`` in the body frame."""
        if model.d != 3:
            raise ValueError(f"a classical 3x3 inertia tensor needs d=3, got d={model.d}")
        inertia = np.asarray(inertia, dtype=float)
        if inertia.shape != (3, 3) or not np.allclose(inertia, inertia.T):
            raise ValueError("inertia tensor must be a symmetric 3x3 matrix")
        _positive("principal moments", np.linalg.eigvalsh(inertia), "a positive tensor")
        com = model._check_coords(com, "centre of mass")
        # Second moment about the centroid from I = tr(S) 1 - S, then the parallel shift.
        s_c = 0.5 * np.trace(inertia) * np.eye(3) - inertia
        return cls.from_moments(model, mass, com, s_c + mass * np.outer(com, com))
