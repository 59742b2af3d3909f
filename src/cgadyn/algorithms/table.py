"""One record per compiled algorithm: what it reads, what it returns, what a fault means.

The records are plain data (this module imports nothing of cgadyn), read twice:

- ``tools/generate_entries.py`` writes ``entries/<name>.py`` from them: for each algorithm
  its one-sample entry, its C-callable form for ``cgadyn._native`` and its parallel batch
  entry, all calling the algorithm's core ``<module>.<name>_core(m, inputs..., [f,]
  outputs..., options..., work) -> status``;
- ``cgadyn.algorithms.calls`` calls those entries: checks and converts the inputs, allocates
  the outputs, registers the C-callable forms with ``cgadyn._native`` and turns a status into
  the message of a ``ValueError``.

Sizes are written with the model's symbols: ``n`` joints, ``nq`` and ``nv`` the sizes of q
and v, ``nl`` link frames.
"""

from __future__ import annotations

from dataclasses import dataclass

SIZES = ("n", "nq", "nv", "nl")
"""The symbols a size may use; ``cgadyn._native`` numbers them -1, -2, -3, -4."""


@dataclass(frozen=True)
class Algorithm:
    """A compiled algorithm.

    ``inputs``: the name and size of each sample array (``("q", "nq")``, ``("v", "nv")``);
    ``forces``: whether it takes external wrenches ``f_ext`` (one per joint);
    ``outputs``: the shape of each result array of one sample;
    ``options``: the names of its integer arguments (a link index, a frame), if any;
    ``nonfinite``: what a non-finite result from finite inputs means;
    ``group``: the module of a ``<name>_group(m, inputs..., [f,] outputs..., start, stop,
    work) -> status`` that a batch calls on each chunk of samples instead of the core on
    each sample (it computes several samples at once), with its own ``workspace_size``.
    """

    name: str
    module: str
    inputs: tuple[tuple[str, str], ...]
    outputs: tuple[tuple[int | str, ...], ...]
    forces: bool = False
    options: tuple[str, ...] = ()
    nonfinite: str = "an overflow"
    group: str = ""

    @property
    def core(self) -> str:
        return f"{self.name}_core"


Q, V, A, TAU = ("q", "nq"), ("v", "nv"), ("a", "nv"), ("tau", "nv")

ALGORITHMS = (
    Algorithm("rnea", "rnea", (Q, V, A), (("nv",),), forces=True),
    Algorithm("aba", "aba", (Q, V, TAU), (("nv",),), forces=True,
              nonfinite="an overflow, or a nearly singular articulated inertia"),
    Algorithm("crba", "crba", (Q,), (("nv", "nv"),)),
    Algorithm("rnea_derivatives", "rnea_derivatives", (Q, V, A), (("nv", "nv"),) * 3,
              forces=True, group="rnea_derivatives_lanes"),
    Algorithm("aba_derivatives", "aba_derivatives", (Q, V, TAU), (("nv", "nv"),) * 3,
              forces=True, nonfinite="an overflow, or a nearly singular articulated inertia",
              group="aba_derivatives_lanes"),
    Algorithm("minverse", "minverse", (Q,), (("nv", "nv"),),
              nonfinite="an overflow, or a nearly singular articulated inertia",
              group="minverse_lanes"),
    Algorithm("motors", "kinematics", (Q,), (("n", 8), ("nl", 8))),
    Algorithm("placements", "kinematics", (Q,), (("nl", 4, 4),)),
    Algorithm("jacobian", "jacobian", (Q,), ((6, "nv"),), options=("link", "frame")),
    Algorithm("energy", "energy", (Q, V), ((2,),)),
    Algorithm("com", "centroidal", (Q, V, A), ((3, 3),),
              nonfinite="a model without mass, or an overflow"),
    Algorithm("centroidal", "centroidal", (Q,), ((6, "nv"), (3,)),
              nonfinite="a model without mass, or an overflow"),
    Algorithm("integrate", "manifold", (Q, V), (("nq",),)),
    Algorithm("difference", "manifold", (("q0", "nq"), ("q1", "nq")), (("nv",),)),
)

BY_NAME = {a.name: a for a in ALGORITHMS}
