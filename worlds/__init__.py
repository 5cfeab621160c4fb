"""Shipped world files (data only)."""
