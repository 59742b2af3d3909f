"""Contact: collision shapes as CGA objects, on links, their signed distances, and the
frictional contact problem with its solvers, ADMM and PGS (docs/contact.md)."""

from .api import shape_distance
from .model import Collision, CollisionModel, collision_distances, collision_model, collision_poses
from .problem import contact_problem
from .shapes import Box, Capsule, ConvexMesh, Cylinder, MeshSimplified, Plane, Shape, Sphere
from .solve import ContactSolveInfo, solve_contacts

__all__ = ["Box", "Capsule", "Collision", "CollisionModel", "ContactSolveInfo", "ConvexMesh",
           "Cylinder", "MeshSimplified", "Plane", "Shape", "Sphere", "collision_distances",
           "collision_model", "collision_poses", "contact_problem", "shape_distance",
           "solve_contacts"]
