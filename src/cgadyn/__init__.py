"""cgadyn: robot dynamics in conformal geometric algebra G(4,1), checked against Pinocchio."""

__version__ = "0.1.0"
