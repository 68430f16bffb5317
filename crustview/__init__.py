"""crustview: the generalized crust algorithm for d-manifolds in R^k, and a viewer for every stage."""

__version__ = "0.1.0"
