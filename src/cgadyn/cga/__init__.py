"""The conformal model G(4,1): null basis, typed subspaces, conventions, inertia."""

from .objects import Circle, Inertia, Line, Motor, Plane, Point, Sphere, Twist, Wrench

__all__ = ["Circle", "Inertia", "Line", "Motor", "Plane", "Point", "Sphere", "Twist", "Wrench"]
