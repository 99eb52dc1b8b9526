"""The word of an L-system, stored compactly in NumPy arrays.

A :class:`ModuleString` holds ``n`` modules as

* ``ids``: ``uint16[n]`` — each module's symbol id in an :class:`Alphabet` (two bytes a
  module keep big words cheap to write: page faults, not arithmetic, bound a step);
* ``offsets``: ``int64[n + 1]`` — module ``i`` has parameters ``values[offsets[i]:offsets[i+1]]``;
* ``values``: ``float64[m]`` — every parameter of every module, in order.

The bracket structure (``match``: the index of the matching bracket; ``parent``: the
module a module grows from on the axial tree; ``depth``) is computed on demand and cached,
by one compiled pass; :meth:`ModuleString.match_vectorised` and
:meth:`ModuleString.parent_vectorised` compute the same with array operations alone.

Examples
--------
>>> w = ModuleString.from_text("F(1)[+F(0.5)]F")
>>> len(w), str(w)
(6, 'F(1)[+F(0.5)]F')
>>> w.match.tolist()
[-1, 4, -1, -1, 1, -1]
>>> w[1:5].symbols()
['[', '+', 'F', ']']
"""

from __future__ import annotations

import math
import re
from collections import Counter
from collections.abc import Iterable, Iterator, Sequence

import numpy as np

from .._jit import road
from ..errors import LSystemSyntaxError, SylvaError

__all__ = [
    "CLOSE",
    "ID_DTYPE",
    "MAX_SYMBOLS",
    "OPEN",
    "Alphabet",
    "ModuleString",
    "format_number",
    "format_symbol",
]

#: While the derivation kernels are not compiled (a fresh install), a kernel call on a word
#: of at most this many modules runs the kernel's Python source (:func:`sylva._jit.road`):
#: milliseconds for such a word, against seconds of compiling.
SMALL_WORD = 100_000
_kernels = road("sylva.lsystem._kernels", size=SMALL_WORD)

OPEN = 0
CLOSE = 1
ID_DTYPE = np.uint16
MAX_SYMBOLS = 65535

# Characters that are syntax in a word and cannot be one-character module names.
# "?" is quoted so that a module ? before P, H, U, L or E is not read back as a query module.
_SYNTAX = set('()",#?') | set(" \t\r\n")


class Alphabet:
    """An append-only table of symbol names; ``[`` is id 0 and ``]`` is id 1.

    Every program and every word derived from it share one alphabet, so ids stay valid.
    """

    __slots__ = ("_names", "_index")

    def __init__(self, names: Iterable[str] = ()) -> None:
        self._names: list[str] = ["[", "]"]
        self._index: dict[str, int] = {"[": OPEN, "]": CLOSE}
        for name in names:
            self.id(name)

    def id(self, name: str) -> int:
        """The id of ``name``, adding it when new."""
        i = self._index.get(name)
        if i is None:
            i = len(self._names)
            if i >= MAX_SYMBOLS:
                raise SylvaError(
                    f"more than {MAX_SYMBOLS} different symbols: {name!r} does not fit"
                )
            self._names.append(name)
            self._index[name] = i
        return i

    def get(self, name: str, default: int = -1) -> int:
        """The id of ``name`` or ``default`` when it is not in the table."""
        return self._index.get(name, default)

    def name(self, i: int) -> str:
        return self._names[i]

    @property
    def names(self) -> Sequence[str]:
        return tuple(self._names)

    def __len__(self) -> int:
        return len(self._names)

    def __contains__(self, name: object) -> bool:
        return name in self._index

    def __repr__(self) -> str:
        return f"Alphabet({self._names[2:]!r})"


def format_number(v: float) -> str:
    """Shortest text that reads back as exactly ``v`` (integers without ``.0``)."""
    v = float(v)
    if v.is_integer() and abs(v) < 1e16:
        return str(int(v))
    if math.isnan(v) or math.isinf(v):
        raise ValueError(f"parameter value {v} cannot be written")
    return repr(v)


def format_symbol(name: str) -> str:
    """A symbol as the ``.lsys`` language writes it (long names in double quotes)."""
    if len(name) == 1 and name not in _SYNTAX:
        return name
    return '"' + name + '"'


_NUM = r"[-+]?(?:\d+\.?\d*(?:[eE][-+]?\d+)?|\.\d+(?:[eE][-+]?\d+)?|True|False|inf|nan)"
_TOKEN = re.compile(
    r'\s*(?:"(?P<long>[^"\n]*)"|(?P<char>\?[PHULE]|[^\s()",#]))\s*(?P<args>\((?P<inner>[^()]*)\))?'
)
_ARG = re.compile(r"\s*(" + _NUM + r")\s*(,|$)")


def _parse_args(inner: str, text: str, pos: int, filename: str | None) -> list[float]:
    out: list[float] = []
    if inner.strip() == "":
        return out
    i = 0
    while i < len(inner):
        m = _ARG.match(inner, i)
        if m is None:
            col = pos + i
            line = text.count("\n", 0, col) + 1
            lcol = col - (text.rfind("\n", 0, col) + 1) + 1
            raise LSystemSyntaxError.at(
                "expected a number as a module parameter", text, line, lcol, filename
            )
        tok = m.group(1)
        out.append(1.0 if tok == "True" else 0.0 if tok == "False" else float(tok))
        i = m.end()
        if m.group(2) == "" and i < len(inner):
            break
    return out




class ModuleString:
    """An immutable sequence of modules stored in NumPy arrays (see the module docstring)."""

    __slots__ = ("alphabet", "ids", "_offsets", "values", "_match", "_parent", "_depth")

    def __init__(
        self,
        alphabet: Alphabet,
        ids: np.ndarray,
        offsets: np.ndarray | None = None,
        values: np.ndarray | None = None,
    ) -> None:
        self.alphabet = alphabet
        self.ids = np.ascontiguousarray(ids, dtype=ID_DTYPE)
        n = self.ids.shape[0]
        self.values = np.ascontiguousarray(
            values if values is not None else np.empty(0), dtype=np.float64
        )
        if offsets is None:
            if self.values.shape[0]:
                raise ValueError("values without offsets")
            self._offsets = None  # no parameters anywhere: made on demand
        else:
            self._offsets = np.ascontiguousarray(offsets, dtype=np.int64)
            if self._offsets.shape[0] != n + 1:
                raise ValueError("offsets must have one entry more than ids")
        self._match: np.ndarray | None = None
        self._parent: np.ndarray | None = None
        self._depth: np.ndarray | None = None

    # ------------------------------------------------------------------ construction
    @classmethod
    def from_text(
        cls, text: str, alphabet: Alphabet | None = None, *, filename: str | None = None
    ) -> ModuleString:
        """Read a word such as ``a"long"[b(5, 6)c]`` (numbers only as parameters)."""
        alphabet = alphabet if alphabet is not None else Alphabet()
        ids: list[int] = []
        counts: list[int] = []
        values: list[float] = []
        pos = 0
        n = len(text)
        while pos < n:
            if text[pos].isspace():
                pos += 1
                continue
            m = _TOKEN.match(text, pos)
            if m is None or m.end() == pos:
                line = text.count("\n", 0, pos) + 1
                col = pos - (text.rfind("\n", 0, pos) + 1) + 1
                raise LSystemSyntaxError.at(
                    f"unexpected {text[pos]!r}: expected a module name (one character, "
                    'or a "quoted" long name) optionally followed by (parameters)',
                    text,
                    line,
                    col,
                    filename,
                )
            name = m.group("long") if m.group("long") is not None else m.group("char")
            args = (
                _parse_args(m.group("inner"), text, m.start("inner"), filename)
                if m.group("args")
                else []
            )
            if name in "[]" and len(name) == 1 and args:
                line = text.count("\n", 0, pos) + 1
                col = pos - (text.rfind("\n", 0, pos) + 1) + 1
                raise LSystemSyntaxError.at(
                    "brackets cannot have parameters", text, line, col, filename
                )
            ids.append(alphabet.id(name))
            counts.append(len(args))
            values.extend(args)
            pos = m.end()
        offsets = np.zeros(len(ids) + 1, np.int64)
        np.cumsum(counts, out=offsets[1:])
        return cls(alphabet, np.array(ids, ID_DTYPE), offsets, np.array(values, np.float64))

    @classmethod
    def from_modules(
        cls,
        modules: Iterable[tuple[str, Sequence[float]] | str],
        alphabet: Alphabet | None = None,
    ) -> ModuleString:
        """Build a word from ``(symbol, params)`` pairs (or bare symbol names)."""
        alphabet = alphabet if alphabet is not None else Alphabet()
        ids: list[int] = []
        counts: list[int] = []
        values: list[float] = []
        for m in modules:
            if isinstance(m, str):
                name, params = m, ()
            else:
                name, params = m
            ids.append(alphabet.id(name))
            counts.append(len(params))
            values.extend(float(p) for p in params)
        offsets = np.zeros(len(ids) + 1, np.int64)
        np.cumsum(counts, out=offsets[1:])
        return cls(alphabet, np.array(ids, ID_DTYPE), offsets, np.array(values, np.float64))

    @classmethod
    def concat(cls, parts: Sequence[ModuleString]) -> ModuleString:
        """Join words that share one alphabet."""
        if not parts:
            raise ValueError("nothing to join")
        alphabet = parts[0].alphabet
        ids = np.concatenate([p.ids for p in parts])
        values = np.concatenate([p.values for p in parts])
        if not any(p.has_params for p in parts):
            return cls(alphabet, ids)
        counts = np.concatenate([np.diff(p.offsets) for p in parts])
        offsets = np.zeros(ids.shape[0] + 1, np.int64)
        np.cumsum(counts, out=offsets[1:])
        return cls(alphabet, ids, offsets, values)

    # ------------------------------------------------------------------ sequence protocol
    def __len__(self) -> int:
        return int(self.ids.shape[0])

    def __getitem__(self, key):
        if isinstance(key, slice):
            start, stop, step = key.indices(len(self))
            if step != 1:
                raise ValueError("a ModuleString slice must be contiguous")
            if not self.has_params:
                return ModuleString(self.alphabet, self.ids[start:stop])
            o = self.offsets[start : stop + 1] if stop > start else self.offsets[start : start + 1]
            vals = self.values[o[0] : o[-1]]
            return ModuleString(self.alphabet, self.ids[start:stop], o - o[0], vals)
        i = int(key)
        if i < 0:
            i += len(self)
        if not 0 <= i < len(self):
            raise IndexError(key)
        return (
            self.alphabet.name(int(self.ids[i])),
            tuple(float(v) for v in self.values[self.offsets[i] : self.offsets[i + 1]]),
        )

    def __iter__(self) -> Iterator[tuple[str, tuple[float, ...]]]:
        names = self.alphabet.names
        vals = self.values.tolist()
        off = self.offsets.tolist()
        for i, s in enumerate(self.ids.tolist()):
            yield names[s], tuple(vals[off[i] : off[i + 1]])

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, ModuleString):
            return NotImplemented
        if len(self) != len(other):
            return False
        if self.alphabet is other.alphabet:
            same_ids = np.array_equal(self.ids, other.ids)
        else:
            same_ids = self.symbols() == other.symbols()
        if not same_ids:
            return False
        if not self.has_params and not other.has_params:
            return True
        return np.array_equal(self.offsets, other.offsets) and np.array_equal(
            self.values, other.values
        )

    __hash__ = None  # type: ignore[assignment]

    def __repr__(self) -> str:
        text = str(self) if len(self) <= 60 else str(self[:60]) + "…"
        return f"ModuleString({text!r}, n={len(self)})"

    def __str__(self) -> str:
        return self.to_text()

    # ------------------------------------------------------------------ views
    @property
    def offsets(self) -> np.ndarray:
        """``int64[n + 1]``: where each module's parameters start in :attr:`values`."""
        if self._offsets is None:
            self._offsets = np.zeros(self.ids.shape[0] + 1, np.int64)
        return self._offsets

    @property
    def has_params(self) -> bool:
        return self.values.shape[0] > 0

    @property
    def nparams(self) -> np.ndarray:
        """``int64[n]``: the number of parameters of each module."""
        return np.diff(self.offsets)

    def params(self, i: int) -> np.ndarray:
        """The parameters of module ``i`` (a view)."""
        return self.values[self.offsets[i] : self.offsets[i + 1]]

    def symbols(self) -> list[str]:
        """The symbol name of every module."""
        names = self.alphabet.names
        return [names[s] for s in self.ids.tolist()]

    def counts(self) -> Counter:
        """How many modules of each symbol the word has."""
        c = np.bincount(self.ids, minlength=len(self.alphabet))
        names = self.alphabet.names
        return Counter({names[i]: int(k) for i, k in enumerate(c) if k})

    def count(self, symbol: str) -> int:
        i = self.alphabet.get(symbol)
        return 0 if i < 0 else int(np.count_nonzero(self.ids == i))

    def to_text(self, *, sep: str = "", float32: bool = False) -> str:
        """The word in ``.lsys`` notation (long names quoted, exact numbers; ``float32``:
        the shortest text of each number as a 32-bit float, cpfg's parameters)."""
        names = [format_symbol(n) for n in self.alphabet.names]
        if not self.has_params:
            return sep.join(names[s] for s in self.ids.tolist())
        vals = self.values.tolist()
        if float32:  # 2.2 as a float is 2.200000047683716 as a double: written 2.2
            vals = [float(str(np.float32(v))) for v in vals]
        off = self.offsets.tolist()
        parts = []
        for i, s in enumerate(self.ids.tolist()):
            a, b = off[i], off[i + 1]
            if a == b:
                parts.append(names[s])
            else:
                parts.append(names[s] + "(" + ",".join(format_number(v) for v in vals[a:b]) + ")")
        return sep.join(parts)

    # ------------------------------------------------------------------ tree structure
    def check_brackets(self, filename: str | None = None) -> None:
        """Raise :class:`~sylva.errors.LSystemSyntaxError` unless brackets balance."""
        d = np.cumsum(
            (self.ids == OPEN).astype(np.int64) - (self.ids == CLOSE).astype(np.int64)
        )
        if d.size and (d.min() < 0 or d[-1] != 0):
            where = int(np.argmax(d < 0)) if d.min() < 0 else len(self)
            raise LSystemSyntaxError(
                f"unbalanced brackets: module {where} of the word "
                + (
                    "closes a branch that was never opened"
                    if d.min() < 0
                    else "leaves a branch open"
                ),
                filename=filename,
            )

    @property
    def match(self) -> np.ndarray:
        """``int64[n]``: index of the matching bracket for ``[``/``]``, else -1.

        Computed in one compiled pass with a stack; :meth:`match_vectorised` computes the
        same without a Python loop and is kept as its reference.
        """
        if self._match is None:
            self._match = _kernels.match_brackets(self.ids)
        return self._match

    def match_vectorised(self) -> np.ndarray:
        """The bracket partners of :attr:`match`, computed with array operations only.

        Brackets are sorted by nesting level and position, and each opening bracket pairs
        with the next bracket of its level.  Unbalanced brackets are left at -1.
        """
        ids = self.ids
        n = ids.shape[0]
        m = np.full(n, -1, np.int64)
        is_open = ids == OPEN
        is_close = ids == CLOSE
        br = np.flatnonzero(is_open | is_close)
        if br.size:
            step = np.where(is_open[br], 1, -1)
            after = np.cumsum(step)
            level = np.where(step > 0, after, after + 1)  # level of the pair
            order = np.lexsort((br, level))
            sb = br[order]
            sl = level[order]
            so = is_open[sb]
            # an opener followed (in its level) by a closer forms a pair
            pair = so[:-1] & ~so[1:] & (sl[:-1] == sl[1:])
            a = sb[:-1][pair]
            b = sb[1:][pair]
            m[a] = b
            m[b] = a
        return m

    def parent_vectorised(self) -> np.ndarray:
        """The parents of :attr:`parent`, computed with array operations only.

        Each module's innermost enclosing ``[`` is found by a sorted search per nesting
        level; the previous module on the same axis by a running maximum over the modules
        sorted by that ``[``; a module first on its axis takes what its ``[`` grows from,
        resolved for all chains at once by pointer jumping (O(log depth) rounds).
        """
        ids = self.ids
        n = ids.shape[0]
        parent = np.full(n, -1, np.int64)
        if n == 0:
            return parent
        is_open = ids == OPEN
        is_close = ids == CLOSE
        is_mod = ~(is_open | is_close)
        depth = np.cumsum(is_open.astype(np.int64) - is_close.astype(np.int64))
        # innermost enclosing opener of every module and opener (-1: the root axis)
        level = np.where(is_open, depth - 1, depth)
        opens = np.flatnonzero(is_open)
        g = np.full(n, -1, np.int64)
        inside = (level > 0) & ~is_close
        if opens.size:
            key_o = depth[opens] * (n + 1) + opens
            order = np.argsort(key_o, kind="stable")
            ks = key_o[order]
            q = np.flatnonzero(inside)
            at = np.searchsorted(ks, level[q] * (n + 1) + q) - 1
            ok = at >= 0
            cand = opens[order[np.maximum(at, 0)]]
            ok &= depth[cand] == level[q]
            g[q[ok]] = cand[ok]
        # the previous module of the same axis (same innermost opener), for modules and openers
        items = np.flatnonzero(is_mod | is_open)
        srt = items[np.lexsort((items, g[items]))]
        gs = g[srt]
        k = np.arange(srt.size)
        last = np.maximum.accumulate(np.where(is_mod[srt], k, -1))
        before = np.concatenate(([-1], last[:-1]))
        same = (before >= 0) & (gs[np.maximum(before, 0)] == gs)
        prev = np.full(n, -2, np.int64)  # -2: none on this axis
        prev[srt] = np.where(same, srt[np.maximum(before, 0)], -2)
        # a module first on its axis grows from what its branch's '[' grows from:
        # pointer jumping over the openers resolves the chains in O(log depth) rounds
        ans = prev.copy()
        ptr = np.where(ans == -2, g, -1)
        todo = np.flatnonzero((ans == -2) & (is_mod | is_open))
        while todo.size:
            p = ptr[todo]
            root = p < 0
            ans[todo[root]] = -1
            todo, p = todo[~root], p[~root]
            found = ans[p] != -2
            ans[todo[found]] = ans[p[found]]
            todo, p = todo[~found], p[~found]
            ptr[todo] = ptr[p]
        parent[is_mod] = ans[is_mod]
        return parent

    def _tree(self) -> None:
        self._parent, self._depth = _kernels.parents(self.ids, self.match)

    @property
    def parent(self) -> np.ndarray:
        """``int64[n]``: the module each module grows from (-1 for roots and brackets)."""
        if self._parent is None:
            self._tree()
        return self._parent

    @property
    def depth(self) -> np.ndarray:
        """``int32[n]``: the branch depth (number of enclosing ``[``) of each module."""
        if self._depth is None:
            self._tree()
        return self._depth

    def max_depth(self) -> int:
        return int(self.depth.max()) if len(self) else 0
