"""Generate ``src/cgadyn/kernels/_generated.py`` (and its batch forms) from the reference algebra.

Every kernel is derived by running the reference ``Multivector`` products of
``cgadyn.algebra`` on sympy symbols in the CGA null basis (``cgadyn.cga.basis``), expanding,
and printing one explicit formula per output coefficient. Sandwiches are printed in two
stages (``T = M X``, then ``<T M~>``), which is how a person would compute them by hand and
costs far fewer operations than the fully expanded quadratic form.

Each kernel is described once, as data (``Kernel``: its arguments and a list of statements:
loads, intermediate values, stores, returned values), derived once per run, and both forms
are printed from that description: the single form, and for the kernels that ``batch`` marks
the ``(B, k)`` form over samples. The script imports only the reference algebra and the
null basis, never the kernels it writes, so it runs even when a generated file is broken.

Usage::

    python tools/generate_kernels.py            # rewrite the file
    python tools/generate_kernels.py --check    # exit 1 if the committed file is stale

``_generated_batch.py`` holds the same formulas as ``(B, k)`` loops over samples with
``prange``; ``--check`` covers both files.

Never edit the generated files by hand: change this script and run it.
"""

from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

import numpy as np
import sympy as sp

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))

from cgadyn.cga.basis import (  # noqa: E402
    MOTOR_BLADES,
    NULL,
    TWIST_BLADES,
    WRENCH_BLADES,
)

TARGET = ROOT / "src" / "cgadyn" / "kernels" / "_generated.py"
BATCH_TARGET = ROOT / "src" / "cgadyn" / "kernels" / "_generated_batch.py"


# --- symbolic helpers ---------------------------------------------------------------------


def symbols(prefix: str, n: int) -> list[sp.Symbol]:
    return list(sp.symbols(f"{prefix}0:{n}", real=True))


def mv(values, blades):
    return NULL.multivector(np.array(values, dtype=object), list(blades))


def clean(expr) -> sp.Expr:
    """Expand, and turn the float signs of reverse/involution into exact rationals."""
    expr = sp.expand(sp.sympify(expr))
    return sp.expand(expr.xreplace({f: sp.nsimplify(f) for f in expr.atoms(sp.Float)}))


def coeffs(m, blades) -> list[sp.Expr]:
    return [clean(c) for c in NULL.coeffs(m, list(blades))]


def all_coeffs(m) -> dict[str, sp.Expr]:
    """Nonzero coefficients of ``m`` on every null-basis blade."""
    c = NULL.coeffs(m)
    out = {}
    for name, v in zip(NULL.blade_names, c, strict=True):
        v = clean(v)
        if v != 0:
            out[name] = v
    return out


def as_float(expr: sp.Expr) -> sp.Expr:
    return expr.xreplace({r: sp.Float(r) for r in expr.atoms(sp.Rational) if not r.is_Integer})


def count_ops(exprs: list[sp.Expr]) -> tuple[int, int]:
    mul = add = 0
    for e in exprs:
        ops = sp.count_ops(e, visual=True)
        d = {str(k): v for k, v in ops.as_coefficients_dict().items()}
        mul += int(d.get("MUL", 0)) + int(d.get("DIV", 0))
        add += int(d.get("ADD", 0)) + int(d.get("SUB", 0))
    return mul, add


# Statements of a kernel's body, printed in either form by ``Kernel.lines``:
#   ("load", names, array, indices)    names = array[index], ... (an index is a tuple)
#   ("let", name, expr)                name = expr
#   ("store", array, index, expr)      array[index] = expr
#   ("add", array, index, name)        array[index] += name
#   ("copy", array, index, source)     array[index] = array[source]
#   ("comment", text)


def load(name: str, sym: list[sp.Symbol]) -> tuple:
    return ("load", [str(x) for x in sym], name, [(i,) for i in range(len(sym))])


def assign_lines(target: str, exprs: list[sp.Expr]) -> list[tuple]:
    return [("store", target, (i,), as_float(e)) for i, e in enumerate(exprs)]


def text(e) -> str:
    return e if isinstance(e, str) else sp.sstr(e)


# --- kernels ------------------------------------------------------------------------------

a8, b8 = symbols("a", 8), symbols("b", 8)
m8 = symbols("m", 8)
v6, w6, u6 = symbols("v", 6), symbols("w", 6), symbols("u", 6)


class Kernel:
    """A kernel described once: ``args`` (arrays, and scalars such as ``p1``, which the batch
    form groups by letter into one array), ``body`` (statements), the ``exprs`` counted for
    its docstring, and ``returns`` (expressions returned by the single form, written to
    ``out`` by the batch form); ``batch`` when a ``(B, k)`` form is wanted."""

    def __init__(self, name, args, doc, body, exprs, returns=None, batch=False):
        self.name, self.args, self.doc, self.body = name, args, doc, body
        self.exprs, self.returns, self.batch = exprs, returns, batch

    @property
    def scalars(self) -> list[str]:
        return [a for a in self.args if re.fullmatch(r"[a-z]\d", a)]

    def lines(self, batched: bool) -> list[str]:
        """The body in one form: single (``a[i]``) or batched (``a[n, i]``, indented)."""
        pad = "        " if batched else "    "

        def at(array, index):
            index = ("n", *index) if batched else index
            return f"{array}[{', '.join(map(str, index))}]"

        out = []
        if batched:
            groups: dict[str, list[str]] = {}
            for name in self.scalars:
                groups.setdefault(name[0], []).append(name)
            out += [f"{pad}{', '.join(g)} = " + ", ".join(at(k, (i,)) for i in range(len(g)))
                    for k, g in groups.items()]
        for st in self.body:
            kind = st[0]
            if kind == "load":
                _, names, array, indices = st
                out.append(f"{pad}{', '.join(names)} = " + ", ".join(at(array, i)
                                                                     for i in indices))
            elif kind == "let":
                out.append(f"{pad}{st[1]} = {text(st[2])}")
            elif kind == "store":
                out.append(f"{pad}{at(st[1], st[2])} = {text(st[3])}")
            elif kind == "copy":
                out.append(f"{pad}{at(st[1], st[2])} = {at(st[1], st[3])}")
            elif kind == "add":
                out.append(f"{pad}{at(st[1], st[2])} += {st[3]}")
            else:
                out.append(f"{pad}# {st[1]}")
        if self.returns is not None:
            if not batched:
                out.append(f"    return {', '.join(text(e) for e in self.returns)}")
            elif len(self.returns) == 1:
                out.append(f"{pad}out[n] = {text(self.returns[0])}")
            else:
                out += [f"{pad}out[n, {i}] = {text(e)}" for i, e in enumerate(self.returns)]
        return out

    def source(self) -> str:
        mul, add = count_ops(self.exprs)
        lines = ["", "", "@kernel", f"def {self.name}({', '.join(self.args)}):",
                 f'    """{self.doc}', "", f"    {mul} multiplications, {add} additions.",
                 '    """']
        return "\n".join(lines + self.lines(batched=False))

    def batch_source(self) -> str:
        """The ``(B, k)`` form: the body in a ``prange`` loop over rows ``n``."""
        arrays = [a for a in self.args if a not in self.scalars]
        groups = list(dict.fromkeys(a[0] for a in self.scalars))
        args = [a for a in arrays if a != "out"] + groups + ["out"]
        mul, add = count_ops(self.exprs)
        lines = ["", "", "@parallel", f"def {self.name}_batch({', '.join(args)}):",
                 f'    """Batch form of ``{self.name}``, one row per sample.', "",
                 "    " + self.doc.split("\n\n")[0], "",
                 f"    {mul} multiplications, {add} additions per sample.", '    """',
                 f"    for n in prange({args[0]}.shape[0]):"]
        return "\n".join(lines + self.lines(batched=True) + ["    return out"])


def motor_mul() -> Kernel:
    out = coeffs(mv(a8, MOTOR_BLADES) * mv(b8, MOTOR_BLADES), MOTOR_BLADES)
    body = [load("a", a8), load("b", b8)] + assign_lines("out", out)
    return Kernel(
        "motor_mul", ["a", "b", "out"],
        "Geometric product of two motors, ``out = a b`` (composition, eq. 5).", body, out,
        batch=True,
    )


def motor_mul_rotor() -> Kernel:
    """a b for a rotor b: its e∞ coefficients are zero and not read."""
    b = b8[:4] + [0, 0, 0, 0]
    out = coeffs(mv(a8, MOTOR_BLADES) * mv(b, MOTOR_BLADES), MOTOR_BLADES)
    body = [load("a", a8), load("b", b8[:4])] + assign_lines("out", out)
    return Kernel(
        "motor_mul_rotor", ["a", "b", "out"],
        "``out = a b`` for a rotor ``b = b0 + b1 e12 + b2 e13 + b3 e23`` (its e∞ coefficients\n"
        "    are not read): a revolute joint's motor about an axis through the frame origin.",
        body, out,
    )


def motor_mul_translator() -> Kernel:
    """a b for a translator b = 1 + b4 e1∞ + b5 e2∞ + b6 e3∞."""
    b = [1, 0, 0, 0] + b8[4:7] + [0]
    out = coeffs(mv(a8, MOTOR_BLADES) * mv(b, MOTOR_BLADES), MOTOR_BLADES)
    body = [load("a", a8), ("load", [str(x) for x in b8[4:7]], "b", [(4,), (5,), (6,)])]
    return Kernel(
        "motor_mul_translator", ["a", "b", "out"],
        "``out = a b`` for a translator ``b = 1 + b4 e1∞ + b5 e2∞ + b6 e3∞`` (only b4..b6\n"
        "    are read): a prismatic joint's motor.",
        body + assign_lines("out", out), out,
    )


def motor_reverse() -> Kernel:
    out = coeffs(~mv(a8, MOTOR_BLADES), MOTOR_BLADES)
    body = [load("a", a8)] + assign_lines("out", out)
    return Kernel("motor_reverse", ["a", "out"], "Reverse of a motor, ``out = ~a``.", body, out,
                  batch=True)


def sandwich(name: str, doc: str, blades_in, blades_out, reverse: bool,
             batch: bool = False) -> Kernel:
    """``out = <M X ~M>`` (or ``<~M X M>``) in two explicit stages."""
    m = mv(m8, MOTOR_BLADES)
    x = mv(v6, blades_in)
    left, right = (~m, m) if reverse else (m, ~m)
    stage = all_coeffs(left * x)
    t = symbols("t", len(stage))
    t_mv = NULL.multivector(np.array(t, dtype=object), list(stage))
    out = coeffs(t_mv * right, blades_out)
    body = [load("m", m8), load("x", v6)]
    body.append(("comment", f"stage 1: T = {'~M' if reverse else 'M'} X on blades "
                             f"{', '.join(stage)}"))
    used = set().union(*(e.free_symbols for e in out))
    body += [("let", str(s), as_float(e)) for s, e in zip(t, stage.values(), strict=True)
             if s in used]
    body.append(("comment", f"stage 2: out = <T {'M' if reverse else '~M'}> on the output "
                             f"blades"))
    body += assign_lines("out", out)
    kept = [e for s, e in zip(t, stage.values(), strict=True) if s in used]
    return Kernel(name, ["m", "x", "out"], doc, body, kept + out, batch=batch)


def commutator(name, doc, blades_a, blades_b, blades_out, sym_a, sym_b,
               batch: bool = True) -> Kernel:
    a, b = mv(sym_a, blades_a), mv(sym_b, blades_b)
    out = coeffs((a * b - b * a) * sp.Rational(1, 2), blades_out)
    body = [load("a", sym_a), load("b", sym_b)] + assign_lines("out", out)
    return Kernel(name, ["a", "b", "out"], doc, body, out, batch=batch)


def twist_wrench_dot() -> Kernel:
    e = clean(np.asarray(mv(v6, TWIST_BLADES).scalar_product(mv(w6, WRENCH_BLADES))).item())
    body = [load("v", v6), load("w", w6)]
    return Kernel(
        "dot",
        ["v", "w"],
        "Inner product ``v · w`` of a twist and a wrench (a scalar).\n\n"
        "    The power of the motion is ``p = -v · w`` (eq. 9).",
        body, [e], returns=[as_float(e)], batch=True,
    )


def inertia_apply() -> Kernel:
    """W = I[V] = -sum_k (I^{e_k} . V) e_k, eq. (15)."""
    isym = [symbols(f"i{k}_", 6) for k in range(6)]
    v = mv(v6, TWIST_BLADES)
    out = []
    for k in range(6):
        element = mv(isym[k], WRENCH_BLADES)
        out.append(clean(-np.asarray(element.scalar_product(v)).item()))
    body = [load("v", v6)]
    for k in range(6):
        body.append(("load", [str(x) for x in isym[k]], "inertia", [(k, j) for j in range(6)]))
    body += assign_lines("out", out)
    return Kernel(
        "inertia_apply", ["inertia", "v", "out"],
        "Apply an inertia tensor to a twist: ``out = I[v] = -Σ_k (I^{e_k} · v) e_k`` (eq. 15).\n\n"
        "    ``inertia[k, j]`` is the coefficient of element I^{e_k} on wrench blade j.",
        body, out, batch=True,
    )


def _adjoint_pattern() -> list[list[sp.Expr]]:
    """Symbolic entries of the wrench adjoint X(M) (to know its structural zeros)."""
    m = mv(m8, MOTOR_BLADES)
    mr = ~m
    x = [[None] * 6 for _ in range(6)]
    for j in range(6):
        unit = [0] * 6
        unit[j] = 1
        col = coeffs(m * mv(unit, WRENCH_BLADES) * mr, WRENCH_BLADES)
        for i in range(6):
            x[i][j] = col[i]
    return x


def wrench_adjoint() -> Kernel:
    """The 6x6 matrix X with <M W ~M>_wrench = X @ W, common products shared (sympy.cse)."""
    x = _adjoint_pattern()
    entries = [(i, j, x[i][j]) for j in range(6) for i in range(6)]
    nonzero = [e for _, _, e in entries if e != 0]
    shared, reduced = sp.cse(nonzero, symbols=sp.numbered_symbols("c"), optimizations="basic")
    body = [load("m", m8), ("comment", "products shared by several entries")]
    body += [("let", str(s_), as_float(e)) for s_, e in shared]
    it = iter(reduced)
    for i, j, e in entries:
        body.append(("store", "out", (i, j), as_float(next(it)) if e != 0 else "0"))
    return Kernel(
        "wrench_adjoint", ["m", "out"],
        "Matrix of the projected wrench sandwich: ``<M W ~M>_wrench = out @ W``.",
        body, [e for _, e in shared] + list(reduced),
    )


def inertia_transform() -> Kernel:
    """Eq. (16): out^{e_j} = M (Σ_k <M I^{e_k} ~M>_{e_j} e_k) ~M, with X the wrench adjoint."""
    x = _adjoint_pattern()
    body = [load("m", m8)]
    body.append(("comment", "stage 1: X, the matrix of the wrench sandwich <M W ~M>_wrench"))
    xs = [[sp.Symbol(f"x{i}{j}") if x[i][j] != 0 else 0 for j in range(6)] for i in range(6)]
    exprs = []
    for i in range(6):
        for j in range(6):
            if x[i][j] != 0:
                body.append(("let", f"x{i}{j}", as_float(x[i][j])))
                exprs.append(x[i][j])
    isym = [[sp.Symbol(f"i{k}{j}") for j in range(6)] for k in range(6)]
    for k in range(6):
        body.append(("load", [str(s) for s in isym[k]], "inertia", [(k, j) for j in range(6)]))
    body.append(("comment", "stage 2: A[k, j] = <M I^{e_k} ~M>_{e_j}"))
    for k in range(6):
        for j in range(6):
            e = sum(isym[k][l] * xs[j][l] for l in range(6))
            exprs.append(e)
            body.append(("let", f"a{k}{j}", e))
    body.append(("comment", "stage 3: out^{e_j} = M (Σ_k A[k, j] e_k) ~M"))
    for j in range(6):
        for mm in range(6):
            e = sum(xs[mm][k] * sp.Symbol(f"a{k}{j}") for k in range(6))
            exprs.append(e)
            body.append(("store", "out", (j, mm), e))
    return Kernel(
        "inertia_transform", ["m", "inertia", "out"],
        "Move an inertia tensor by a motor: ``out = M * I`` (eq. 16).\n\n"
        "    Satisfies eq. (17): ``M I[V] ~M = (M * I)[M V ~M]``.",
        body, exprs, batch=True,
    )


def adjoint_apply(transpose: bool) -> Kernel:
    """out = X w (wrench sandwich) or out = Xᵀ v (inverse twist sandwich)."""
    x = _adjoint_pattern()
    xs = [[sp.Symbol(f"x{i}{j}") if x[i][j] != 0 else 0 for j in range(6)] for i in range(6)]
    v = v6
    body = [load("v", v)]
    used = sorted({str(e) for row in xs for e in row if e != 0})
    body.append(("load", used, "x", [(int(u[1]), int(u[2])) for u in used]))
    if transpose:
        exprs = [sum(xs[i][j] * v[i] for i in range(6)) for j in range(6)]
        name = "adjoint_apply_transpose"
        doc = ("Inverse twist sandwich from the adjoint: ``out = Xᵀ v = ~M v M``.\n\n"
               "    The power pairing is invariant (eq. 9), so the matrix of ``~M (·) M`` on\n"
               "    twists is the transpose of the wrench adjoint X of ``M (·) ~M``.")
    else:
        exprs = [sum(xs[i][j] * v[j] for j in range(6)) for i in range(6)]
        name = "adjoint_apply"
        doc = "Wrench sandwich from the adjoint: ``out = X w = <M w ~M>_wrench``."
    body += assign_lines("out", exprs)
    return Kernel(name, ["x", "v", "out"], doc, body, exprs)


def inertia_congruence(accumulate: bool = False, downdate: bool = False) -> Kernel:
    """out = X I Xᵀ (or out += X I Xᵀ) for a symmetric I, upper triangle computed and
    mirrored; ``downdate``: out += X (I - w gᵀ) Xᵀ, the upper triangle of I - w gᵀ formed
    as it is loaded."""
    x = _adjoint_pattern()
    xs = [[sp.Symbol(f"x{i}{j}") if x[i][j] != 0 else 0 for j in range(6)] for i in range(6)]
    isym = [[sp.Symbol(f"i{min(k, j)}{max(k, j)}") for j in range(6)] for k in range(6)]
    used = sorted({str(e) for row in xs for e in row if e != 0})
    body = [("load", used, "x", [(int(u[1]), int(u[2])) for u in used])]
    exprs = []
    if downdate:
        body += [load("w", w6), load("g", symbols("g", 6))]
    for k in range(6):
        names = [f"{'r' if downdate else 'i'}{k}{j}" for j in range(k, 6)]
        body.append(("load", names, "inertia", [(k, j) for j in range(k, 6)]))
    if downdate:
        body.append(("comment", "I - w gᵀ, upper triangle"))
        for k in range(6):
            for j in range(k, 6):
                e = sp.Symbol(f"r{k}{j}") - sp.Symbol(f"w{k}") * sp.Symbol(f"g{j}")
                exprs.append(e)
                body.append(("let", f"i{k}{j}", e))
    # X is block upper triangular, [[X11, X12], [0, X22]]; I = [[A, B], [Bᵀ, C]]:
    #   X I Xᵀ = [[X11 A X11ᵀ + Y X12ᵀ + X12 Zᵀ, Y X22ᵀ], [., X22 C X22ᵀ]]
    # with Z = X11 B and Y = Z + X12 C: 207 multiplications instead of 270.
    assert all(xs[i][j] == 0 for i in range(3, 6) for j in range(3))
    X11 = [[xs[i][j] for j in range(3)] for i in range(3)]
    X12 = [[xs[i][j + 3] for j in range(3)] for i in range(3)]
    X22 = [[xs[i + 3][j + 3] for j in range(3)] for i in range(3)]
    A = [[isym[i][j] for j in range(3)] for i in range(3)]
    B = [[isym[i][j + 3] for j in range(3)] for i in range(3)]
    C = [[isym[i + 3][j + 3] for j in range(3)] for i in range(3)]

    def emit(name, e):
        exprs.append(e)
        body.append(("let", name, e))
        return sp.Symbol(name.split("[")[0]) if "[" not in name else None

    r3 = range(3)
    body.append(("comment", "Z = X11 B, Y = Z + X12 C, T = A X11ᵀ, U = C X22ᵀ"))
    Z = [[emit(f"z{i}{j}", sum(X11[i][k] * B[k][j] for k in r3)) for j in r3] for i in r3]
    Y = [[emit(f"y{i}{j}", Z[i][j] + sum(X12[i][k] * C[k][j] for k in r3)) for j in r3]
         for i in r3]
    T = [[emit(f"t{i}{j}", sum(A[i][k] * X11[j][k] for k in r3)) for j in r3] for i in r3]
    U = [[emit(f"u{i}{j}", sum(C[i][k] * X22[j][k] for k in r3)) for j in r3] for i in r3]
    op = "+=" if accumulate else "="
    body.append(("comment", f"out {op} X I Xᵀ, upper triangle of the diagonal blocks, mirrored"))

    def store(i, j, e):
        exprs.append(e)
        if accumulate:  # one local, added to both mirrored entries
            body.append(("let", f"o{i}{j}", e))
            body.append(("add", "out", (i, j), f"o{i}{j}"))
            if i != j:
                body.append(("add", "out", (j, i), f"o{i}{j}"))
        else:
            body.append(("store", "out", (i, j), e))
            if i != j:
                body.append(("copy", "out", (j, i), (i, j)))

    for i in r3:
        for j in range(i, 3):
            store(i, j, sum(X11[i][k] * T[k][j] + Y[i][k] * X12[j][k] + X12[i][k] * Z[j][k]
                            for k in r3))
    for i in r3:
        for j in r3:
            store(i, j + 3, sum(Y[i][k] * X22[j][k] for k in r3))
    for i in r3:
        for j in range(i, 3):
            store(i + 3, j + 3, sum(X22[i][k] * U[k][j] for k in r3))
    if downdate:
        return Kernel(
            "inertia_congruence_downdate_add", ["x", "inertia", "w", "g", "out"],
            "``out += M * (I - w gᵀ)`` (eq. 16) from the wrench adjoint X of M, for\n"
            "    ``I - w gᵀ`` symmetric (its upper triangle is read): the articulated inertia\n"
            "    ``Ĩ = Î - U Gᵀ`` of a one-dof joint (Algorithm 1, second line, with\n"
            "    ``G = U / D``) moved into its parent's, formed as ``Î`` is loaded so that\n"
            "    it never goes through memory. ``inertia_congruence_add`` otherwise.",
            body, exprs,
        )
    if accumulate:
        return Kernel(
            "inertia_congruence_add", ["x", "inertia", "out"],
            "``out += M * I`` (eq. 16) for a symmetric inertia, from the wrench adjoint X of\n"
            "    M: ``inertia_congruence`` that adds into ``out`` (a parent's articulated\n"
            "    inertia) instead of overwriting it; the count leaves out those 36 additions.",
            body, exprs,
        )
    return Kernel(
        "inertia_congruence", ["x", "inertia", "out"],
        "``out = M * I`` (eq. 16) for a symmetric inertia, from the wrench adjoint X of M.\n\n"
        "    Eq. (16) applies the sandwich twice, once to each element and once to the\n"
        "    transposed set: as matrices ``out = X I Xᵀ``. ``out`` may alias ``inertia``.",
        body, exprs,
    )


def translator_rotor() -> Kernel:
    """M = T R with T = 1 - ½ p e∞ and R a rotor, from scalars."""
    p = sp.symbols("p1:4", real=True)
    r = sp.symbols("r0:4", real=True)
    t = mv([1, 0, 0, 0, -p[0] / 2, -p[1] / 2, -p[2] / 2, 0], MOTOR_BLADES)
    out = coeffs(t * mv(list(r) + [0, 0, 0, 0], MOTOR_BLADES), MOTOR_BLADES)
    return Kernel(
        "translator_rotor", ["p1", "p2", "p3", "r0", "r1", "r2", "r3", "out"],
        "Motor ``out = T R``: the rotor ``r0 + r1 e12 + r2 e13 + r3 e23`` followed by the\n"
        "    translator ``T = 1 - ½ p e∞`` (Dorst's convention for e0·e∞ = -1).",
        assign_lines("out", out), out,
    )


def motor_translation() -> Kernel:
    """p = -2 <M ~R>_{e∞} where R is the rotor part of M."""
    m = mv(m8, MOTOR_BLADES)
    r = mv(m8[:4] + [0, 0, 0, 0], MOTOR_BLADES)
    p = [sp.factor_terms(clean(-2 * c)) for c in coeffs(m * ~r, MOTOR_BLADES)[4:7]]
    return Kernel(  # -2 factored out: 15 multiplications where the expanded form takes 24
        "motor_translation", ["m"],
        "Translation ``p`` of a normalised motor ``M = T R``: ``p = -2 <M ~R>_(e∞)``.",
        [load("m", m8)], p, returns=p, batch=True,
    )


KERNELS = [
    motor_mul,
    motor_mul_rotor,
    motor_mul_translator,
    motor_reverse,
    lambda: sandwich(
        "twist_sandwich", "Move a twist by a motor: ``out = M X ~M`` (eq. 4; twists are closed).",
        TWIST_BLADES, TWIST_BLADES, reverse=False, batch=True,
    ),
    lambda: sandwich(
        "twist_sandwich_rev", "Move a twist by the inverse motor: ``out = ~M X M``.",
        TWIST_BLADES, TWIST_BLADES, reverse=True,
    ),
    lambda: sandwich(
        "wrench_sandwich",
        "Move a wrench by a motor: ``out = <M X ~M>_wrench`` (eq. 4, then projected).\n\n"
        "    A wrench is not closed under the CGA sandwich: translating ``e01`` adds ``e∞``\n"
        "    terms that pair to zero with every twist (eq. 9); the projection drops them.",
        WRENCH_BLADES, WRENCH_BLADES, reverse=False, batch=True,
    ),
    lambda: sandwich(
        "wrench_sandwich_rev",
        "Move a wrench by the inverse motor: ``out = <~M X M>_wrench`` (projected).",
        WRENCH_BLADES, WRENCH_BLADES, reverse=True,
    ),
    lambda: commutator(
        "twist_cross", "Commutator of two twists, ``out = a × b`` (eqs. 10-11): the Lie bracket.",
        TWIST_BLADES, TWIST_BLADES, TWIST_BLADES, v6, u6,
    ),
    lambda: commutator(
        "twist_cross_wrench",
        "Commutator of a twist and a wrench, ``out = <a × b>_wrench`` (eqs. 10-11).\n\n"
        "    The dropped ``e0∞`` term pairs to zero with every twist.",
        TWIST_BLADES, WRENCH_BLADES, WRENCH_BLADES, v6, w6,
    ),
    twist_wrench_dot,
    inertia_apply,
    wrench_adjoint,
    inertia_transform,
    translator_rotor,
    motor_translation,
    lambda: adjoint_apply(transpose=False),
    lambda: adjoint_apply(transpose=True),
    inertia_congruence,
    lambda: inertia_congruence(accumulate=True),
    lambda: inertia_congruence(accumulate=True, downdate=True),
]

HEADER = '''"""Explicit-formula kernels of CGA G(4,1) for motors, twists, wrenches and inertias.

GENERATED by tools/generate_kernels.py from the reference algebra: do not edit by hand.

Layouts (coefficients in the null basis, e0·e∞ = -1):
    motor  (8,): {motor}
    twist  (6,): {twist}
    wrench (6,): {wrench}
    inertia (6, 6): inertia[k, j] = coefficient of element I^(e_k) on wrench blade j.
Each kernel writes into ``out`` (which may alias an input) and allocates nothing, so it can
be called from other compiled code, where it is inlined (``straight.kernel``: emitted from this
source, or with ``CGADYN_KERNELS=numba`` inlined by numba): a recursion is then one
function without calls.
"""

from .straight import kernel
'''


def derive() -> list[Kernel]:
    """Every kernel, derived once."""
    return [make() for make in KERNELS]


def generate(kernels: list[Kernel]) -> str:
    """Text of ``_generated.py``."""
    text_ = HEADER.format(
        motor=", ".join(MOTOR_BLADES), twist=", ".join(TWIST_BLADES),
        wrench=", ".join(WRENCH_BLADES),
    )
    return text_ + "".join(k.source() + "\n" for k in kernels)


# --- batch forms -------------------------------------------------------------------------

BATCH_HEADER = '''"""Batch forms of kernels of ``_generated.py``, one sample per row.

GENERATED by tools/generate_kernels.py from the same formulas: do not edit by hand.

Every argument gains a leading sample axis (motor (B, 8), twist/wrench (B, 6), inertia
(B, 6, 6)), and a returned value is written to ``out`` ((B,) or (B, 3)). Each kernel writes
into ``out`` and returns it; nothing checks shapes here (see ``cgadyn.kernels.batch``).
Indexing is direct, ``a[n, i]``: row views cost several times the arithmetic. Only the
kernels that numpy-level code calls (``cgadyn.cga``) have a batch form.
"""

# ruff: noqa: E501
from numba import prange

from .._jit import parallel
'''


def generate_batch(kernels: list[Kernel]) -> str:
    """Text of ``_generated_batch.py``: the batch form of every kernel marked ``batch``."""
    return BATCH_HEADER + "".join(k.batch_source() + "\n" for k in kernels if k.batch)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="fail if the file is stale")
    parser.add_argument("--out", type=Path, default=TARGET.parent,
                        help="the directory to write into (default: the package's kernels)")
    args = parser.parse_args()
    kernels = derive()
    stale = 0
    for name, text_ in (("_generated.py", generate(kernels)),
                        ("_generated_batch.py", generate_batch(kernels))):
        target = args.out / name
        if args.check:
            current = target.read_text() if target.exists() else ""
            if current != text_:
                print(f"{target} is stale: run python tools/generate_kernels.py", file=sys.stderr)
                stale = 1
            else:
                print(f"{target} is up to date")
            continue
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_text(text_)
        print(f"wrote {target}")
    return stale


if __name__ == "__main__":
    raise SystemExit(main())
