"""Physics validation of plans in Drake (adapter: the only package importing pydrake)."""
