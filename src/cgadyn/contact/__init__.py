"""Contact, its first step: collision shapes as CGA objects, on links, and their signed
distances (docs/contact.md). No contact forces yet."""

from .api import shape_distance
from .model import Collision, CollisionModel, collision_distances, collision_model, collision_poses
from .shapes import Box, Capsule, ConvexMesh, Cylinder, MeshSimplified, Plane, Shape, Sphere

__all__ = ["Box", "Capsule", "Collision", "CollisionModel", "ConvexMesh", "Cylinder",
           "MeshSimplified", "Plane", "Shape", "Sphere", "collision_distances",
           "collision_model", "collision_poses", "shape_distance"]
