"""Contact, its first step: collision shapes as CGA objects, on links, and their signed
distances (docs/contact.md), the ground and the contacts with it. No contact forces yet."""

from .api import shape_distance
from .model import Collision, CollisionModel, collision_distances, collision_model, collision_poses
from .shapes import Box, Capsule, ConvexMesh, Cylinder, MeshSimplified, Plane, Shape, Sphere
from .world import Contacts, World, ground_contacts

__all__ = ["Box", "Capsule", "Collision", "CollisionModel", "Contacts", "ConvexMesh",
           "Cylinder", "MeshSimplified", "Plane", "Shape", "Sphere", "World",
           "collision_distances", "collision_model", "collision_poses", "ground_contacts",
           "shape_distance"]
