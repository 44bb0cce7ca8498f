"""One greedy-insertion run (paper §5): the Delaunay triangulator, the priority queue of candidates, the assessment.

:class:`GreedyRun` is the loop that :func:`~persistri.impl.terrain.greedy.greedy_insertion`
drives: it lays the grid's first two triangles, and each :meth:`GreedyRun.step`
inserts the worst sample (:meth:`~persistri.impl.terrain.delaunay.Triangulator.insert`),
measures the new triangles' samples (:mod:`~persistri.impl.terrain.plane_errors`)
and queues their candidates; :meth:`GreedyRun.current_error` pops the dead
entries (lazy invalidation).  Each queue entry is one Python integer (:class:`QueueKeys`):
the run's largest structure after the complex, it costs 48 bytes an entry where a tuple of
an error, a triangle id and a sample cost 128–160.  A module of its own because it is the terrain's
per-insertion work: the compiled twin (docs/performance.md) compiles it with
mypyc, while ``greedy_insertion``, which validates the caller's arguments and
raises its own errors, stays interpreted.
"""

from __future__ import annotations

import heapq
from collections.abc import Callable
from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

from persistri.impl.geometry.grid_predicates import GridPredicates2
from persistri.impl.complex.structure import Complex
from persistri.impl.complex.two_complex import TwoComplex
from persistri.impl.stats import Stats
from persistri.impl.terrain.delaunay import Insertion, Samples, TriDatum, Triangulator
from persistri.impl.terrain.plane_errors import CHUNK, apex_first, fan_plane_errors, plane_errors, ranks

__all__ = ["GreedyRun", "QueueKeys", "COMPILED", "PYTHON_ERRORS"]

IntArray = NDArray[np.intp]
FloatArray = NDArray[np.float64]


_PYTHON_ARGMAX: Final = 128
"""Up to this many new samples per insertion the candidates are chosen on a Python list; above it, by numpy
over the whole fan at once (:meth:`GreedyRun._queue`).

A fan of a few dozen samples costs less as ``max`` and ``index`` on a list than as numpy calls; above about a
hundred the list's ``tolist``, ``max`` and ``index`` cost more than the fan's five numpy calls (timeit,
2026-11-28: 2.5 µs against 3.5 µs at 64 samples, 7.3 µs against 3.7 µs at 279, 160 µs against 4.9 µs at
1,566, six triangles).  Both choose the same sample (the first of largest error).
"""


def _where(side: NDArray[np.int8], sign: int, kind: np.dtype[np.signedinteger[Any]]) -> Samples:
    """The indices where ``side == sign``, as ``kind``, found :data:`~persistri.impl.terrain.plane_errors.CHUNK`
    entries at a time (``flatnonzero`` of the whole would be an ``intp`` array of the grid's size). O(len(side))."""
    parts = [
        (np.flatnonzero(side[lo : lo + CHUNK] == sign) + lo).astype(kind) for lo in range(0, side.size, CHUNK)
    ]
    out: Samples = np.concatenate(parts) if parts else np.zeros(0, dtype=kind)
    return out


COMPILED: Final[bool] = not __file__.endswith(".py")
"""Whether this module runs compiled (the twin, docs/performance.md)."""

PYTHON_ERRORS: Final[int] = 256 if COMPILED else 64
"""Up to this many samples in a fan their errors are measured in one loop on Python floats and the candidates
chosen in it (:meth:`GreedyRun._queue_small`); above it, with numpy (:func:`~persistri.impl.terrain.plane_errors.fan_plane_errors`,
then :meth:`GreedyRun._queue`).  The same floats and candidates either way.  On 5,000 of Jacksboro's
insertions (median fan 14 samples) numpy's path costs 11–17 µs a fan whatever its size; the loop about
5 µs plus 0.2 µs a sample interpreted, and about 5 µs up to 256 samples compiled (most of it the queue's
keys): hence a bound for each build."""

_GATHER_HEIGHTS: Final[int] = 32
"""From this many samples :meth:`GreedyRun._queue_small` gathers a fan's heights with one numpy call and a
``tolist`` (about 7 K instructions, then a list read a sample) instead of reading each through the heights'
buffer (about 200–300 instructions a sample, compiled; cachegrind, 2026-11-28).  The same floats."""

_TOP: Final = (1 << 63) - 1
"""The largest bit pattern of a non-negative float64 read as an integer (the sign bit clear)."""
ID_BITS: Final = 64
"""Bits of a queue key's triangle id: ids count the triangles a run makes, one by one, from 0."""


class QueueKeys:
    """The priority queue's entries as single integers: ``(error, triangle id, sample)`` packed so that
    integer order is the order of ``(−error, triangle id, sample)`` tuples.

    A positive float64's bit pattern, read as an integer, grows with the float, so ``_TOP − bits(e)``
    falls as ``e`` grows; it fills the high field, the triangle id (below ``2^64``: ids number the
    triangles one run makes) the next :data:`ID_BITS` bits and the sample (below ``n``, the grid's
    samples) the low ``bits(n − 1)``.  The greatest error comes first, ties go to the older triangle,
    exactly as with the tuples, and :meth:`error` gives back the very float (its bits).  A key of a
    2,048² grid has 149 bits: a Python integer of 48 bytes, where the tuple with its float and its two
    integers took 128 bytes (interpreted; 160 compiled, where mypyc boxes the tuple's fields anew).
    O(1) per key.
    """

    __slots__ = ("sample_bits", "id_shift", "error_shift", "sample_mask", "id_mask", "as_float", "as_bits")

    def __init__(self, n: int) -> None:
        self.sample_bits = max(1, (n - 1).bit_length())
        self.id_shift = self.sample_bits
        self.error_shift = self.sample_bits + ID_BITS
        self.sample_mask = (1 << self.sample_bits) - 1
        self.id_mask = (1 << ID_BITS) - 1
        # One 8-byte buffer seen as a float64 and as an int64: writing a float and reading the int gives its
        # bit pattern, and back (no struct call, no tuple).
        buffer = bytearray(8)
        self.as_float: Any = memoryview(buffer).cast("d")
        self.as_bits: Any = memoryview(buffer).cast("q")

    def key(self, error_bits: int, tid: int, sample: int) -> int:
        """The key of a candidate: ``error_bits`` is its positive error's float64 bit pattern (:meth:`bits`)."""
        return ((_TOP - error_bits) << self.error_shift) | (tid << self.id_shift) | sample

    def tid(self, key: int) -> int:
        """The triangle id of a key."""
        return (key >> self.id_shift) & self.id_mask

    def sample(self, key: int) -> int:
        """The sample (the candidate) of a key."""
        return key & self.sample_mask

    def error(self, key: int) -> float:
        """The error of a key, the same float that was queued."""
        self.as_bits[0] = _TOP - (key >> self.error_shift)
        out: float = self.as_float[0]
        return out

    def bits(self, error: float) -> int:
        """The bit pattern of a float64 as a (signed 64-bit) integer: non-negative and growing with a
        non-negative ``error`` (as ``errors.view(np.int64)`` gives it for an array)."""
        self.as_float[0] = error
        out: int = self.as_bits[0]
        return out


class GreedyRun:
    """One greedy-insertion run over the heights ``z`` of a ``shape`` grid: the triangulator and the priority queue.

    ``structure`` is the 2-complex the versions are made in (its map backend chosen and checked by the
    caller); ``stats``, ``check`` and ``stepwise`` as for
    :func:`~persistri.impl.terrain.greedy.greedy_insertion`.  Laying the first two triangles is
    O(rows · cols); each :meth:`step` is one insertion.
    """

    def __init__(
        self,
        z: FloatArray,
        shape: tuple[int, int],
        structure: TwoComplex[TriDatum],
        stats: Stats | None,
        check: bool,
        stepwise: bool = False,
    ) -> None:
        rows, cols = shape
        self.z = z
        # The heights as a buffer of Python floats read one at a time (the few samples and vertices of an
        # insertion): an index into a memoryview costs a tenth of numpy's ``item`` or of a gather of a few
        # samples and their ``tolist``, and gives the same float.
        self.heights: Any = z.data
        self.pred = GridPredicates2(shape, stats=stats)
        self.structure = structure
        # The triangulator keeps neighbour records (edge_index: the look-ups of the cavity search read them
        # instead of the complex's maps), except in counted runs, which count the paper's look-ups.  Strict
        # conflicts: a sample on a circumcircle is not in conflict (delaunay's module docstring says why).
        self.T = Triangulator(self.pred, self.structure, check=check, stepwise=stepwise, edge_index=True, strict=True)
        n = rows * cols
        self.keys = QueueKeys(n)
        self.heap: list[int] = []
        self.cols = cols
        # Corners counterclockwise in (x, y): (0, 0), (cols-1, 0), (cols-1, rows-1), (0, rows-1).
        a, b, c, d = 0, cols - 1, n - 1, n - cols
        self.corners = (a, b, c, d)
        P = self.pred
        # The diagonal: the one that is Delaunay under the predicates' tie-breaking (the corners are cocircular).
        if P.incircle(a, b, c, d) < 0:
            t1, t2, u, w = (a, b, c), (a, c, d), a, c
        else:
            t1, t2, u, w = (b, c, d), (a, b, d), b, d
        side = self._sides(u, w, shape)
        # t1 is right of the diagonal u → w, t2 left of it (closed triangles: a sample on the diagonal goes by SoS).
        kind = self.T.sample_dtype
        self.T.begin([(t1, _where(side, -1, kind)), (t2, _where(side, 1, kind))])
        del side
        inserted = np.array(self.corners, dtype=np.intp)
        for tid, tri in list(self.T.tri_of.items()):
            if self.T.infinite in tri:
                continue
            found = self.structure.data(self.T.complex, tri)
            assert found is not None
            own = found[0][1]
            if own.size:
                t = apex_first(np.array([tri], dtype=np.intp), ranks(np.array(tri, dtype=np.intp), inserted))
                self._queue_one(tid, own, lambda s: plane_errors(cols, self.z, t, np.array([s.size]), s))

    def _sides(self, u: int, w: int, shape: tuple[int, int]) -> NDArray[np.int8]:
        """For every grid sample, the SoS side of the diagonal ``u → w`` (±1), and 0 at the four corners.

        Exact: ``(w − u) × (q − u)`` on integer coordinates (int64: |coordinates| < 2^25), row blocks at a
        time; the samples exactly on the diagonal take the predicates' SoS sign.  O(rows · cols), one byte each.
        """
        rows, cols = shape
        n = rows * cols
        uy, ux = divmod(u, cols)
        wy, wx = divmod(w, cols)
        ex, ey = wx - ux, wy - uy
        side = np.empty(n, dtype=np.int8)
        block = max(1, CHUNK // cols)
        xs = np.arange(cols, dtype=np.int64) - ux
        for r0 in range(0, rows, block):
            r1 = min(rows, r0 + block)
            ys = np.arange(r0, r1, dtype=np.int64) - uy
            cross = (ys * ex)[:, None] - ey * xs[None, :]
            side[r0 * cols : r1 * cols] = np.sign(cross).ravel()
        on = np.flatnonzero(side == 0)
        on = on[(on != u) & (on != w)]
        if on.size:
            side[on] = self.pred.orient2d_batch(u, w, on)
        side[list(self.corners)] = 0
        return side

    def _queue(self, tids: list[int], counts: list[int], samples: Samples, err: FloatArray) -> None:
        """Queue the candidate — the first sample of largest error — of each triangle with samples and error > 0."""
        heap = self.heap
        push = heapq.heappush
        start = 0
        es, ts = self.keys.error_shift, self.keys.id_shift
        if err.size <= _PYTHON_ARGMAX:
            # Few samples (most insertions): Python's max and index on a list beat a numpy call per triangle.
            # A candidate's bit pattern is read through the keys' buffer, per candidate: a list of every
            # sample's bit pattern made an int object per sample, 2 % more instructions per run than floats
            # (which Python keeps on a free list; cachegrind, Jacksboro to 10,000 points).
            errs = err.tolist()
            sample = samples.item
            as_float, as_bits = self.keys.as_float, self.keys.as_bits
            for tid, cnt in zip(tids, counts):
                if cnt:
                    stop = start + cnt
                    if cnt == 1:
                        e = errs[start]
                        if e > 0.0:
                            as_float[0] = e
                            push(heap, ((_TOP - as_bits[0]) << es) | (tid << ts) | sample(start))
                    else:
                        seg = errs[start:stop]
                        e = max(seg)
                        if e > 0.0:
                            as_float[0] = e
                            push(heap, ((_TOP - as_bits[0]) << es) | (tid << ts) | sample(start + seg.index(e)))
                    start = stop
            return
        # Many samples: each triangle's largest error by one reduction over the fan (the triangles with samples
        # only: reduceat reads an empty segment as its next element), and its first sample as the first of
        # the fan's positions holding its triangle's maximum at or after the triangle's start.  The same
        # floats and samples as the list's max and index, unless an error is NaN (max is then not the
        # maximum): those fans go triangle by triangle, as before.
        sizes = np.array(counts, dtype=np.intp)
        ends = np.cumsum(sizes)
        held = sizes > 0
        starts = (ends - sizes)[held]
        largest = np.maximum.reduceat(err, starts)
        if bool((largest == largest).all()):
            at = np.flatnonzero(err == np.repeat(largest, sizes[held]))
            firsts = samples[at[np.searchsorted(at, starts)]].tolist()
            lived = [tid for tid, cnt in zip(tids, counts) if cnt]
            for tid, e, s in zip(lived, largest.tolist(), firsts):
                if e > 0.0:
                    push(heap, self.keys.key(self.keys.bits(e), tid, s))
            return
        for tid, cnt in zip(tids, counts):
            if cnt:
                part = err[start : start + cnt]
                i = int(part.argmax())
                e = float(part[i])
                if e > 0.0:
                    push(heap, self.keys.key(self.keys.bits(e), tid, int(samples[start + i])))
                start += cnt

    def _queue_small(
        self, tids: list[int], counts: list[int], samples: Samples, xp: float, yp: float, zp: float,
        gxs: list[float], gys: list[float],
    ) -> None:
        """Measure the samples of a small fan on Python floats and queue each triangle's candidate.

        The error of a sample ``(x, y)`` of fan triangle ``i`` is ``|z − ((gx_i (x − xp) + zp) + gy_i (y − yp))|``:
        the same IEEE operations in the same order as :func:`~persistri.impl.terrain.plane_errors.fan_plane_errors`
        (a product does not depend on its operands' order), so the same floats, and the candidate is the first
        sample of largest error, as :meth:`_queue` chooses it.  For the few samples of most insertions (a median
        of 9 on the Jacksboro DEM) one loop costs less than the dozen numpy calls on arrays of that size.
        O(len(samples)).
        """
        ss: list[Any] = samples.tolist()
        # The heights: one gather for a fan of many samples, else read one at a time through the buffer
        # (each read there costs a few hundred instructions; the gather and its list a few thousand in all).
        hs: list[float] = self.z[samples].tolist() if len(ss) >= _GATHER_HEIGHTS else []
        gather = bool(hs)
        zv = self.heights
        cols = self.cols
        heap = self.heap
        push = heapq.heappush
        es, ts = self.keys.error_shift, self.keys.id_shift
        as_float, as_bits = self.keys.as_float, self.keys.as_bits
        j = 0
        for tid, cnt, gx, gy in zip(tids, counts, gxs, gys):
            if not cnt:
                continue
            stop = j + cnt
            best = 0.0
            at = -1
            while j < stop:
                # The sample as the list's object (a height read through the buffer takes it as it is; compiled,
                # an unboxed int would be boxed anew), its value unboxed once for the arithmetic.
                qo = ss[j]
                q: int = qo
                y = q // cols
                z: float
                if gather:
                    z = hs[j]
                else:
                    z = zv[qo]
                e = abs(z - ((gx * ((q - y * cols) - xp) + zp) + gy * (y - yp)))
                if e > best:  # strictly: an equal error later is not the first
                    best = e
                    at = j
                j += 1
            if at >= 0:
                as_float[0] = best
                push(heap, ((_TOP - as_bits[0]) << es) | (tid << ts) | ss[at])

    def _queue_one(self, tid: int, samples: Samples, measure: Callable[[Samples], FloatArray]) -> None:
        """Queue the candidate of one triangle with very many samples, their errors (``measure``) taken
        :data:`~persistri.impl.terrain.plane_errors.CHUNK` at a time: the first sample of largest error, as
        :meth:`_queue` chooses it, without an array of every sample's error (8 bytes a sample: twice the
        samples' own list, on the first insertions of a large grid)."""
        best, at = 0.0, -1
        for lo in range(0, samples.size, CHUNK):
            err = measure(samples[lo : lo + CHUNK])
            i = int(err.argmax())
            e = float(err[i])
            if e > best:  # strictly: an equal error later is not the first
                best, at = e, lo + i
        if at >= 0:
            heapq.heappush(self.heap, self.keys.key(self.keys.bits(best), tid, int(samples[at])))

    def _assess(self, ins: Insertion) -> None:
        """Measure the samples of the insertion's new triangles and queue their candidates (:func:`fan_errors`).

        Vectorised over the whole fan; for a fan of very many samples (no pooled array: ``ins.samples``
        is None), triangle by triangle.
        """
        samples = ins.samples
        if samples is not None and not samples.size:
            return
        # A vertex's coordinates are (i mod cols, i div cols), exact as floats: the predicates' rows
        # (GridPredicates2.xy) computed here, without a call per vertex; its height read from the buffer.
        coords, cols, zv = self.pred.coordinates, self.cols, self.heights
        p: int = ins.point
        yi = p // cols
        xp, yp = float(p - yi * cols), float(yi)
        zp: float = zv[p]
        gxs: list[float] = []
        gys: list[float] = []
        ring = ins.rays
        v: int = ring[0]
        yi = v // cols
        x1, y1 = float(v - yi * cols), float(yi)
        z1: float = zv[v]
        for i in range(1, len(ring)):
            v = ring[i]
            yi = v // cols
            x2, y2 = float(v - yi * cols), float(yi)
            z2: float = zv[v]
            dx1, dy1, dz1 = x1 - xp, y1 - yp, z1 - zp
            dx2, dy2, dz2 = x2 - xp, y2 - yp, z2 - zp
            det = dx1 * dy2 - dx2 * dy1
            gxs.append((dz1 * dy2 - dz2 * dy1) / det)
            gys.append((dx1 * dz2 - dx2 * dz1) / det)
            x1, y1, z1 = x2, y2, z2
        tids = [tid for tid, _ in ins.created]
        if samples is not None and samples.size <= PYTHON_ERRORS:
            self._queue_small(tids, ins.counts, samples, xp, yp, zp, gxs, gys)
            return
        if samples is None:
            z = self.z
            for tid, gx, gy, part in zip(tids, gxs, gys, ins.lists):
                if part.size:
                    self._queue_one(tid, part, lambda s: fan_plane_errors(coords, z, xp, yp, zp, [gx], [gy], None, s))
            return
        err = fan_plane_errors(coords, self.z, xp, yp, zp, gxs, gys, ins.fan_index, samples)
        self._queue(tids, ins.counts, samples, err)

    def current_error(self) -> float:
        """The maximum error of the current mesh: the queue's top, once dead triangles are popped.

        Entries of dead triangles stay in the queue until they surface (lazy invalidation); when they
        exceed a quarter of the live triangles (and 1,024) the queue is rebuilt without them, so that it
        stays within 1.25 times the mesh's size (O(queue) then, O(1) amortised per entry: about four
        entries per dead one).  Its order is a total one (error, then triangle id), so the rebuilt queue
        pops exactly what the old one would have.  (Up to twice the mesh's size, the bound before, the dead
        entries took 11 MB at the end of a 2,048² run, measured.)  A triangle is alive when the
        triangulator's neighbour record at its id is (``Triangulator.adj``), or, in a counted run (no
        records), when its id is in ``tri_of``.
        """
        heap = self.heap
        T = self.T
        ts, tm = self.keys.id_shift, self.keys.id_mask
        live = T.live
        adj = T.adj
        if adj is None:
            alive = T.tri_of
            if len(heap) > live + (live >> 2) + 1024:
                heap[:] = [key for key in heap if ((key >> ts) & tm) in alive]
                heapq.heapify(heap)
            while heap and ((heap[0] >> ts) & tm) not in alive:
                heapq.heappop(heap)
        else:
            if len(heap) > live + (live >> 2) + 1024:
                heap[:] = [key for key in heap if adj[(key >> ts) & tm] is not None]
                heapq.heapify(heap)
            while heap and adj[(heap[0] >> ts) & tm] is None:
                heapq.heappop(heap)
        return self.keys.error(heap[0]) if heap else 0.0

    def step(self) -> Insertion:
        """Insert the current worst sample; return what the insertion did."""
        key = heapq.heappop(self.heap)
        keys = self.keys
        ins = self.T.insert(key & keys.sample_mask, (key >> keys.id_shift) & keys.id_mask)
        self._assess(ins)
        return ins

    def run(
        self,
        e_stop: float | None,
        k_stop: int | None,
        history: bool,
        versions: list[Complex[TriDatum]],
        inserted: Any,
        errors: Any,
        tick: Callable[[int], Any] | None,
    ) -> None:
        """Insert until the mesh's maximum error is 0 or at most ``e_stop``, or it has ``k_stop`` vertices.

        The loop of :func:`~persistri.impl.terrain.greedy.greedy_insertion`, here so that the twin runs it
        compiled: appends each level's maximum error (:meth:`current_error`, the last one that of the final
        mesh) to ``errors`` and each inserted sample to ``inserted`` (arrays or lists), and each new
        version to ``versions`` (``history``) or as its only entry; calls ``tick(1)`` after each insertion.
        O(1) per insertion besides :meth:`step`.
        """
        while True:
            err = self.current_error()
            errors.append(err)
            if err == 0.0 or (e_stop is not None and err <= e_stop) or (k_stop is not None and len(inserted) >= k_stop):
                return
            ins = self.step()
            inserted.append(ins.point)
            if history:
                versions.append(ins.version)
            else:
                versions[0] = ins.version
            if tick is not None:
                tick(1)
