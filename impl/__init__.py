"""persistri.impl — the structures and algorithms of *Persistent Triangulations*.

* :mod:`persistri.impl.maps` — persistent ``ORD_MAP`` backends;
* :mod:`persistri.impl.stats` — the operation counts of the paper's §4;
* :mod:`persistri.impl.cli` — the ``persistri`` command.
"""
