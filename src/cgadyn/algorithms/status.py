"""How compiled code reports a fault: a status code it returns, never an exception it raises.

Raising from numba's nopython mode leaks references to the call's arrays, so every
compiled entry point returns an int64 status instead and Python raises the ``ValueError``
(``cgadyn.algorithms.errors`` words it). A status packs the fault, the joint it concerns
and, for batches, the sample::

    status = code + 256 (joint + 1) + 2**24 sample        (0: no fault)
"""

from __future__ import annotations

from .._jit import inline

OK = 0
NONFINITE_INPUT = 1
"""An input holds NaN or inf (Python finds which array, index and joint)."""
NONFINITE_RESULT = 2
"""The result is not finite although every input is: an overflow."""
SINGULAR = 3
"""ABA: the articulated inertia of a joint's subtree along its motion is not positive."""
QUATERNION = 4
"""A joint's quaternion (a free flyer's, a spherical joint's) is far from unit length."""
WRONG_SHAPE = 5
"""An array's shape does not fit the model (batch entries check their inputs)."""
DIVERGED = 6
"""A rollout: a velocity past the bound one step can resolve (``sim.rollout``)."""

DELASSUS_SINGULAR = 7
"""Constraints: the Delassus matrix is singular at a row (reported in the joint's place);
Python names the constraint (``constraints.solve``)."""
CONSTRAINTS_CONFLICT = 8
"""A rollout: the proximal solve of the constraint forces ended with a row (reported in the
joint's place) violated past ``constraints.core.CONFLICT``: the set has no solution."""
CONTACT_UNSOLVED = 9
"""A rollout with contact: neither ADMM nor PGS solved a step's contact problem
(``sim.contact``)."""
CONTACT_PAIR = 10
"""A rollout with contact: the penetration depth of a pair of shapes was not computed (a
curved overlap whose bounds do not meet, K9a), reported in the joint's place by the pair's
index (``sim.pairs``): the step would otherwise go on without that contact."""

JOINT_UNIT = 256
SAMPLE_UNIT = 1 << 24


@inline
def fault(code, joint):
    """The status of ``code`` at ``joint`` (-1: no joint in particular)."""
    return code + JOINT_UNIT * (joint + 1)


@inline
def at_sample(status, sample):
    """A one-sample status within a batch."""
    return status + SAMPLE_UNIT * sample if status != OK else OK


def decode(status: int) -> tuple[int, int, int]:
    """``(code, joint, sample)`` of a status; joint -1 for none."""
    return (status % JOINT_UNIT, (status // JOINT_UNIT) % (SAMPLE_UNIT // JOINT_UNIT) - 1,
            status // SAMPLE_UNIT)
