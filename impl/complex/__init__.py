"""Persistent simplicial complexes (paper §2): vertices, simplices and the complex functor."""
