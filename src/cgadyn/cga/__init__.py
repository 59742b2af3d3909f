"""The conformal model G(4,1): null basis, typed subspaces, conventions, inertia."""
