"""The bulldozer 3D convex hull (paper §3 and Appendix A) and its inputs, checks and outputs."""
