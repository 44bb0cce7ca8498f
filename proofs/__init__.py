"""persistri's proofs: sympy proofs of the algebraic identities the algorithms rely on, and CrossHair contract checks.

Run them all with ``python -m proofs`` from the repository root (see ``proofs/README.md``).
"""
