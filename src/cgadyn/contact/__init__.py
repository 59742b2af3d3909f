"""Contact: collision shapes as CGA objects, on links, their signed distances, the ground
and the contact points with it, the frictional contact problem with its solvers, ADMM and
PGS, and the velocity-level step that joins them (docs/contact.md)."""

from .api import shape_distance
from .bodies import Body, with_bodies
from .criteria import ContactCriteria, step_criteria
from .model import Collision, CollisionModel, collision_distances, collision_model, collision_poses
from .obstacles import Obstacle
from .problem import contact_problem
from .settings import ContactSettings
from .shapes import (
    Box,
    Capsule,
    ConvexMesh,
    Cylinder,
    Ellipsoid,
    MeshSimplified,
    Plane,
    Shape,
    Sphere,
)
from .solve import ContactSolveInfo, solve_contacts
from .static_world import static_world
from .step import ContactStep, contact_step
from .world import Contacts, World, ground_contacts

__all__ = ["Body", "Box", "Capsule", "Collision", "CollisionModel", "ContactCriteria",
           "ContactSettings",
           "ContactSolveInfo", "ContactStep",
           "Contacts", "ConvexMesh", "Cylinder", "Ellipsoid", "MeshSimplified", "Obstacle", "Plane",
           "Shape", "Sphere",
           "World", "collision_distances", "collision_model", "collision_poses",
           "contact_problem", "contact_step", "ground_contacts", "shape_distance",
           "solve_contacts", "static_world", "step_criteria", "with_bodies"]
