"""The paper's experiments, regenerated: Figs. 6, 7, 8 (§4, convex hull) and 11 (§5, terrain).

One module per figure — :mod:`~persistri.impl.experiments.fig6`,
:mod:`~persistri.impl.experiments.fig7`, :mod:`~persistri.impl.experiments.fig8`,
:mod:`~persistri.impl.experiments.fig11` — each with a ``run_figN`` that measures
and returns records, a ``write_figN`` that writes ``figN.csv``, ``figN.png`` and
``figN.md`` (the paper's report beside ours), and ``figN`` doing both.
:mod:`~persistri.impl.experiments.counts` holds the counted hull runs Figs. 6
and 7 share, :mod:`~persistri.impl.experiments.dems` the two real DEMs of
Fig. 11, :mod:`~persistri.impl.experiments.output` the file writing, and
:mod:`~persistri.impl.experiments.suite` runs several figures at a preset scale
(the command ``persistri experiments``).
"""
