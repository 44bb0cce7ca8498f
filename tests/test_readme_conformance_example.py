"""test_my_map.py — check a persistent map of your own against persistri's ORD_MAP conformance suite."""

from bisect import bisect_left

from persistri.spec import NATURAL_ORDER, NotFound
from persistri.spec.conformance import OrdMapConformance


class SortedTupleMap:
    """A persistent map as a pair of sorted tuples (keys, values); every update copies them."""

    Key = NATURAL_ORDER

    def empty(self):
        return ((), ())

    def isEmpty(self, m):
        return not m[0]

    def numItems(self, m):
        return len(m[0])

    def singleton(self, k, v):
        return ((k,), (v,))

    def find(self, m, k):
        i = bisect_left(m[0], k)
        return (m[1][i],) if i < len(m[0]) and m[0][i] == k else None

    def lookup(self, m, k):
        found = self.find(m, k)
        if found is None:
            raise NotFound(k)
        return found[0]

    def inDomain(self, m, k):
        return self.find(m, k) is not None

    def insertWith(self, f, m, k, v):
        ks, vs = m
        i = bisect_left(ks, k)
        if i < len(ks) and ks[i] == k:
            return ks, vs[:i] + (f(vs[i], v),) + vs[i + 1 :]
        return ks[:i] + (k,) + ks[i:], vs[:i] + (v,) + vs[i:]

    def insert(self, m, k, v):
        return self.insertWith(lambda old, new: new, m, k, v)

    def remove(self, m, k):
        ks, vs = m
        i = bisect_left(ks, k)
        if i == len(ks) or ks[i] != k:
            raise NotFound(k)
        return (ks[:i] + ks[i + 1 :], vs[:i] + vs[i + 1 :]), vs[i]

    def listItemsi(self, m):
        return list(zip(*m))

    def listKeys(self, m):
        return list(m[0])

    def foldli(self, f, init, m):
        for k, v in zip(*m):
            init = f(k, v, init)
        return init

    def _check(self, m):  # optional: the suite calls it after every step
        assert len(m[0]) == len(m[1]) and all(a < b for a, b in zip(m[0], m[0][1:]))


class TestSortedTupleMap(OrdMapConformance):
    structure = SortedTupleMap()
    workload_size = 5_000  # each update copies O(n): 10^5 keys would be slow
