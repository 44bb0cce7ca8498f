"""Benchmarks: commands that measure persistri against its peers in the same run (``persistri bench``)."""
