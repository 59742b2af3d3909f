"""Typed CGA objects: thin wrappers over float arrays that call the compiled kernels.

``Motor`` (8 floats), ``Twist`` and ``Wrench`` (6 floats, eqs. 7-8) and ``Inertia`` (6x6,
eqs. 12-14) hold ``values`` with any batch axes first, ``(..., 8)``; their operations run the
batch kernels of ``cgadyn.kernels.batch``. ``Point``, ``Line``, ``Plane``, ``Circle`` and
``Sphere`` are backed by the reference ``Multivector`` (outer-product form, X = e0 + x + ½x² e∞).
A motor moves every object by the sandwich ``M X ~M`` (eq. 4): ``M(obj)`` or ``M.apply(obj)``.
Signs and the link to Pinocchio are those of ``cgadyn.cga.conventions``.
"""

from __future__ import annotations

import numpy as np

from .._threads import PARALLEL_LOCK
from ..algebra import Multivector
from ..algebra.multivector import format_terms
from ..kernels import batch as KB
from . import conventions as C
from .basis import MOTOR_BLADES, NULL, TWIST_BLADES, WRENCH_BLADES, e0, einf, motor_mv


def _run(kernel, out_tail: tuple[int, ...], *args: tuple[np.ndarray, int]) -> np.ndarray:
    """Call a batch kernel on ``(array, core ndim)`` pairs with broadcast batch axes."""
    batch = np.broadcast_shapes(*(a.shape[: a.ndim - k] for a, k in args))
    size = int(np.prod(batch, dtype=int))
    flat = []
    for a, k in args:
        core = a.shape[a.ndim - k :]
        if a.shape != batch + core:
            a = np.broadcast_to(a, batch + core)
        # C-contiguous and writable: one compiled specialisation per kernel
        flat.append(np.require(a, float, ["C", "W"]).reshape((size,) + core))
    out = np.empty((size,) + out_tail)
    with PARALLEL_LOCK:
        kernel(*flat, out)
    return out.reshape(batch + out_tail)


def _each(fn, a: np.ndarray, k: int, out_tail: tuple[int, ...]) -> np.ndarray:
    """Apply a single-sample function over the batch axes of ``a`` (core ndim ``k``)."""
    batch = a.shape[: a.ndim - k]
    rows = a.reshape((-1,) + a.shape[a.ndim - k :])
    return np.array([fn(r) for r in rows]).reshape(batch + out_tail)


class _Array:
    """A float array of shape ``batch + CORE`` whose last axis runs over ``BLADES``."""

    CORE: tuple[int, ...] = ()
    BLADES: tuple[str, ...] = ()

    def __init__(self, values):
        v = np.asarray(values, dtype=float)
        name = type(self).__name__
        if v.shape[v.ndim - len(self.CORE) :] != self.CORE or v.ndim < len(self.CORE):
            raise ValueError(f"{name} needs an array of shape (..., {self.CORE}), got {v.shape}")
        if not np.all(np.isfinite(v)):
            raise ValueError(f"{name} contains NaN or inf")
        self.values = v

    @property
    def batch_shape(self) -> tuple[int, ...]:
        return self.values.shape[: self.values.ndim - len(self.CORE)]

    def __getitem__(self, index):
        if not self.batch_shape:
            raise IndexError(f"a single {type(self).__name__} has no batch axis to index")
        return type(self)(self.values[index])

    def __len__(self) -> int:
        if not self.batch_shape:
            raise TypeError(f"a single {type(self).__name__} has no length")
        return self.batch_shape[0]

    def __array__(self, dtype=None, copy=None):
        return self.values if dtype is None else self.values.astype(dtype)

    def allclose(self, other, **kw) -> bool:
        return type(other) is type(self) and bool(np.allclose(self.values, other.values, **kw))

    def __repr__(self) -> str:
        name = type(self).__name__
        if self.batch_shape:
            return f"{name}(batch {self.batch_shape})"
        if len(self.CORE) == 2:
            return f"{name}(\n{np.array2string(self.values, precision=6)})"
        return f"{name}({format_terms(self.values, self.BLADES)})"


class _Bivector(_Array):
    """Common linear structure of twists and wrenches (6 coefficients)."""

    CORE = (6,)

    def __add__(self, other):
        if type(other) is not type(self):
            return NotImplemented
        return type(self)(self.values + other.values)

    def __sub__(self, other):
        if type(other) is not type(self):
            return NotImplemented
        return type(self)(self.values - other.values)

    def __neg__(self):
        return type(self)(-self.values)

    def __mul__(self, s):
        if isinstance(s, _Array):
            return NotImplemented
        return type(self)(self.values * np.asarray(s, dtype=float)[..., None])

    __rmul__ = __mul__

    def mv(self) -> Multivector:
        """The reference multivector."""
        return NULL.multivector(self.values, list(self.BLADES))


class Twist(_Bivector):
    """A twist ``V`` on ``e23, e13, e12, e1∞, e2∞, e3∞`` (eq. 7)."""

    BLADES = TWIST_BLADES

    @classmethod
    def from_pinocchio(cls, motion) -> Twist:
        """From Pinocchio's ``Motion`` or its vector ``[v, ω]`` (..., 6)."""
        return cls(C.twist_from_motion(getattr(motion, "vector", motion)))

    def to_pinocchio(self) -> np.ndarray:
        """Pinocchio's motion vector ``[v, ω]``."""
        return C.motion_from_twist(self.values)

    def cross(self, other: Twist | Wrench) -> Twist | Wrench:
        """Commutator ``V × X`` (eqs. 10-11): a twist for a twist, a wrench for a wrench."""
        if isinstance(other, Twist):
            return Twist(_run(KB.twist_cross_batch, (6,), (self.values, 1), (other.values, 1)))
        if isinstance(other, Wrench):
            out = _run(KB.twist_cross_wrench_batch, (6,), (self.values, 1), (other.values, 1))
            return Wrench(out)
        raise TypeError(f"cannot take the commutator of a Twist with {type(other).__name__}")

    def dot(self, wrench: Wrench) -> np.ndarray | float:
        """Inner product ``V · W`` (the power is ``p = -V · W``, eq. 9)."""
        if not isinstance(wrench, Wrench):
            raise TypeError(f"a Twist pairs with a Wrench, not {type(wrench).__name__}")
        out = _run(KB.dot_batch, (), (self.values, 1), (wrench.values, 1))
        return out if out.ndim else float(out)

    def power(self, wrench: Wrench) -> np.ndarray | float:
        """Power ``p = -V · W = v·f + ω·n`` (eq. 9)."""
        return -self.dot(wrench)

    def exp(self) -> Motor:
        """The motor ``exp(V / 2)`` of moving with this twist for unit time (eq. 6)."""
        return Motor.exp(self)


class Wrench(_Bivector):
    """A wrench ``W`` on ``e23, e13, e12, e01, e02, e03`` (eq. 8)."""

    BLADES = WRENCH_BLADES

    @classmethod
    def from_pinocchio(cls, force) -> Wrench:
        """From Pinocchio's ``Force`` or its vector ``[f, n]`` (..., 6)."""
        return cls(C.wrench_from_force(getattr(force, "vector", force)))

    def to_pinocchio(self) -> np.ndarray:
        """Pinocchio's force vector ``[f, n]``."""
        return C.force_from_wrench(self.values)

    def dot(self, twist: Twist) -> np.ndarray | float:
        """Inner product ``W · V`` (symmetric)."""
        return twist.dot(self)

    def power(self, twist: Twist) -> np.ndarray | float:
        """Power ``p = -V · W`` (eq. 9)."""
        return twist.power(self)


class Inertia(_Array):
    """Inertia tensor: six elements ``I^{e_k}`` on the wrench blades (eqs. 12-14), ``I[k, j]``."""

    CORE = (6, 6)
    BLADES = WRENCH_BLADES

    def __init__(self, values, check: bool = True):
        super().__init__(values)
        if check:
            P = self.values
            scale = max(1.0, float(np.abs(P).max(initial=0.0)))
            if not np.allclose(P, np.swapaxes(P, -1, -2), atol=1e-10 * scale):
                raise ValueError("inertia tensor must be symmetric")
            if np.linalg.eigvalsh(P).min(initial=0.0) < -1e-10 * scale:
                raise ValueError("inertia tensor must be positive semi-definite")

    @classmethod
    def from_parameters(cls, mass: float, com, rotational_inertia) -> Inertia:
        """Body of ``mass`` with centre of mass ``com`` and 3x3 inertia about it (eqs. 18-19)."""
        return cls(C.inertia_from_parameters(mass, com, rotational_inertia))

    @classmethod
    def from_pinocchio(cls, inertia) -> Inertia:
        """From ``pin.Inertia`` or its 6x6 matrix (order ``[v, ω]``)."""
        m = inertia.matrix() if hasattr(inertia, "matrix") else inertia
        return cls(C.inertia_from_pinocchio(m))

    def to_pinocchio(self) -> np.ndarray:
        """Pinocchio's 6x6 spatial inertia matrix (order ``[v, ω]``)."""
        return C.inertia_to_pinocchio(self.values)

    @property
    def mass(self) -> np.ndarray | float:
        m = self.values[..., 3, 3]
        return m if m.ndim else float(m)

    def apply(self, twist: Twist) -> Wrench:
        """``W = I[V] = -Σ_k (I^{e_k} · V) e_k`` (eq. 15)."""
        if not isinstance(twist, Twist):
            raise TypeError(f"an Inertia maps a Twist, not {type(twist).__name__}")
        return Wrench(_run(KB.inertia_apply_batch, (6,), (self.values, 2), (twist.values, 1)))

    __call__ = apply

    def transform(self, motor: Motor) -> Inertia:
        """``M * I`` (eq. 16): this inertia, given in frame B, expressed in frame A."""
        out = _run(KB.inertia_transform_batch, (6, 6), (motor.values, 1), (self.values, 2))
        return Inertia(out, check=False)

    def __add__(self, other):
        if not isinstance(other, Inertia):
            return NotImplemented
        return Inertia(self.values + other.values, check=False)


class Motor(_Array):
    """A motor ``M = T R`` on ``1, e12, e13, e23, e1∞, e2∞, e3∞, e123∞`` (eqs. 4-6)."""

    CORE = (8,)
    BLADES = MOTOR_BLADES

    @classmethod
    def identity(cls, batch: tuple[int, ...] = ()) -> Motor:
        v = np.zeros(tuple(batch) + (8,))
        v[..., 0] = 1.0
        return cls(v)

    @classmethod
    def from_matrix(cls, T) -> Motor:
        """From rigid 4x4 homogeneous matrices (..., 4, 4); ``ValueError`` if not rigid."""
        return cls(_each(C.motor_from_matrix, np.asarray(T, dtype=float), 2, (8,)))

    @classmethod
    def from_quaternion(cls, quat, translation=(0.0, 0.0, 0.0)) -> Motor:
        """From a quaternion ``(w, x, y, z)`` and a translation."""
        return cls(C.motor_from_quaternion(quat, translation))

    @classmethod
    def from_axis_angle(cls, axis, angle: float, translation=(0.0, 0.0, 0.0)) -> Motor:
        """Rotation by ``angle`` about ``axis`` through the origin, then a translation."""
        return cls(C.motor_from_axis_angle(axis, angle, translation))

    @classmethod
    def rotor(cls, axis, angle: float) -> Motor:
        """The rotor ``R = exp(-θ/2 u*)`` of a rotation about ``axis`` through the origin."""
        return cls.from_axis_angle(axis, angle)

    @classmethod
    def translator(cls, t) -> Motor:
        """The translator ``T = 1 - ½ t e∞`` (..., 3)."""
        t = C._vec(t, 3, "translation")
        v = np.zeros(t.shape[:-1] + (8,))
        v[..., 0] = 1.0
        v[..., 4:7] = -0.5 * t
        return cls(v)

    @classmethod
    def exp(cls, twist: Twist) -> Motor:
        """``exp(V / 2)``: the motor of moving with ``twist`` for unit time (eq. 6)."""
        return cls(_run(KB.twist_exp_batch, (8,), (twist.values, 1)))

    def log(self) -> Twist:
        """The twist ``V`` with ``exp(V / 2) = M`` (rotation angle in [0, 2π))."""
        return Twist(_run(KB.motor_log_batch, (6,), (self.normalized().values, 1)))

    def reverse(self) -> Motor:
        return Motor(_run(KB.motor_reverse_batch, (8,), (self.values, 1)))

    __invert__ = reverse

    def inverse(self) -> Motor:
        """The inverse motion ``~M`` of the normalised motor."""
        return self.normalized().reverse()

    def normalized(self) -> Motor:
        """Projected back onto ``M ~M = 1``."""
        if np.any(np.sum(self.values[..., :4] ** 2, axis=-1) < 1e-300):
            raise ValueError("motor has a zero rotor part: it cannot be normalised")
        return Motor(_run(KB.motor_normalize_batch, (8,), (self.values, 1)))

    def matrix(self) -> np.ndarray:
        """4x4 homogeneous matrix (..., 4, 4) of the (normalised) motor."""
        return C.matrix_from_motor(self.values)

    def quaternion(self) -> np.ndarray:
        """Unit quaternion ``(w, x, y, z)`` of the rotation (..., 4)."""
        return _each(C.quaternion_from_motor, self.values, 1, (4,))

    def translation(self) -> np.ndarray:
        """Translation ``t`` (..., 3) of the normalised motor ``M = T R``."""
        return _run(KB.motor_translation_batch, (3,), (self.normalized().values, 1))

    def mv(self) -> Multivector:
        return motor_mv(self.values)

    def __mul__(self, other):
        """Composition ``a b``: the pose ``A @ B`` (eq. 5). Use ``M(obj)`` to move objects."""
        if not isinstance(other, Motor):
            return NotImplemented
        return Motor(_run(KB.motor_mul_batch, (8,), (self.values, 1), (other.values, 1)))

    def apply(self, obj):
        """Move ``obj`` by the sandwich ``M X ~M`` (eq. 4); wrenches are then projected."""
        if isinstance(obj, Twist):
            return Twist(_run(KB.twist_sandwich_batch, (6,), (self.values, 1), (obj.values, 1)))
        if isinstance(obj, Wrench):
            out = _run(KB.wrench_sandwich_batch, (6,), (self.values, 1), (obj.values, 1))
            return Wrench(out)
        if isinstance(obj, Inertia):
            return obj.transform(self)
        if isinstance(obj, Motor):
            return self * obj * self.reverse()
        if isinstance(obj, Geometric):
            m = self.mv()
            return type(obj)(m * obj.mv * ~m)
        raise TypeError(f"a Motor cannot move a {type(obj).__name__}")

    __call__ = apply


# --- geometric objects of the reference algebra ------------------------------------------


class Geometric:
    """A blade of CGA in outer-product form, backed by the reference ``Multivector``."""

    def __init__(self, mv: Multivector):
        if not isinstance(mv, Multivector):
            raise TypeError(f"{type(self).__name__} wraps a Multivector, not {type(mv).__name__}")
        self.mv = mv

    def contains(self, point: Point, tol: float = 1e-9) -> np.ndarray | bool:
        """Whether ``point`` lies on this object: ``X ∧ A = 0``."""
        c = np.abs((point.mv ^ self.mv).coeffs).max(axis=-1)
        scale = np.abs(self.mv.coeffs).max(axis=-1) * np.abs(point.mv.coeffs).max(axis=-1)
        ok = c <= tol * np.maximum(scale, 1.0)
        return ok if np.ndim(ok) else bool(ok)

    def __repr__(self) -> str:
        if self.mv.batch_shape:
            return f"{type(self).__name__}(batch {self.mv.batch_shape})"
        return f"{type(self).__name__}({NULL.repr(self.mv)})"


class Point(Geometric):
    """A conformal point ``X = e0 + x + ½ x² e∞`` (up projection)."""

    def __init__(self, x):
        if isinstance(x, Multivector):
            super().__init__(x)
            return
        x = C._vec(x, 3, "point coordinates")
        half = 0.5 * np.sum(x * x, axis=-1)
        super().__init__(NULL.multivector(
            np.concatenate([np.ones(x.shape[:-1] + (1,)), x, half[..., None]], axis=-1),
            ["e0", "e1", "e2", "e3", "e∞"],
        ))

    def down(self) -> np.ndarray:
        """Euclidean coordinates ``x`` (down projection, dividing by the weight ``-X·e∞``)."""
        c = NULL.coeffs(self.mv, ["e1", "e2", "e3"])
        w = -np.asarray((self.mv | einf).scalar_part())
        return c / np.asarray(w)[..., None]


class Line(Geometric):
    """The line ``A ∧ B ∧ e∞`` through two points."""

    @classmethod
    def through(cls, a: Point, b: Point) -> Line:
        return cls(a.mv ^ b.mv ^ einf)


class Plane(Geometric):
    """The plane ``A ∧ B ∧ C ∧ e∞`` through three points."""

    @classmethod
    def through(cls, a: Point, b: Point, c: Point) -> Plane:
        return cls(a.mv ^ b.mv ^ c.mv ^ einf)


class Circle(Geometric):
    """The circle ``A ∧ B ∧ C`` through three points."""

    @classmethod
    def through(cls, a: Point, b: Point, c: Point) -> Circle:
        return cls(a.mv ^ b.mv ^ c.mv)


class Sphere(Geometric):
    """The sphere ``A ∧ B ∧ C ∧ D`` through four points."""

    @classmethod
    def through(cls, a: Point, b: Point, c: Point, d: Point) -> Sphere:
        return cls(a.mv ^ b.mv ^ c.mv ^ d.mv)

    @classmethod
    def from_center_radius(cls, center, radius: float) -> Sphere:
        """Dual of ``S = C - ½ r² e∞`` (``X · S = 0`` on the sphere)."""
        if not np.isfinite(radius) or radius <= 0:
            raise ValueError(f"radius must be finite and positive, got {radius}")
        s = Point(center).mv - einf * (0.5 * float(radius) ** 2)
        return cls(s * _pseudoscalar())


def _pseudoscalar() -> Multivector:
    from .basis import e1, e2, e3

    return e0 ^ e1 ^ e2 ^ e3 ^ einf


__all__ = [
    "Circle", "Geometric", "Inertia", "Line", "Motor", "Plane", "Point", "Sphere", "Twist",
    "Wrench",
]
