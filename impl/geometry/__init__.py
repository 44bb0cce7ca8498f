"""Exact geometric predicates: integer scaling, float filters, Simulation of Simplicity."""
