"""L-system textures: a small, self-contained 2D L-system drawn into (tileable) images.

``sylva.texture`` does not import :mod:`sylva.lsystem` (the import rules keep the two
apart), so this module carries its own minimal pipeline for textures:

1. :func:`rewrite` — context-free parallel rewriting on single characters.  Every symbol
   without a rule maps to itself.  A rule's successor may be a string, or a list of
   ``(probability, successor)`` pairs for stochastic rules (drawn with
   ``numpy.random.default_rng(seed)``).  Each symbol also carries a *generation*: symbols
   written inside brackets by a rule applied in step ``k`` get generation ``k``; the
   others inherit the generation of the symbol they replaced.  So the trunk is generation
   0 and a branch sprouted in step 3 is generation 3.
2. :func:`turtle` — a 2D turtle (seed 003 §4.8, Table 1) turns the string into
   :class:`Segments`:

   ======  ==============================================================
   ``F``   draw forward (the symbols in ``draw``; default ``"F"``)
   ``f``   move forward without drawing (the symbols in ``move``; ``"fG"``)
   ``B``   draw backward
   ``+``   turn left (counter-clockwise) by ``angle``; ``-`` turns right
   ``|``   turn around
   ``[``   push the state (position, heading, width, colour); ``]`` pops it
   ``#``   widen the line by ``width_increment``; ``!`` narrows it
   ``;``   advance the colour index by ``color_increment``
   digits  a count before ``+ - F f B``: ``3+`` is ``+++`` (L-Systems Explorer)
   ``R``   draw forward by a random length, ``step`` times a seeded uniform factor in
           ``random_step`` (WWW L-System Explorer, seed 003 §5.9 Table 3)
   ``<``   descend one nesting level: the step is multiplied by ``step_scale`` and the
           angle by ``angle_scale`` (the explorer's Δ step and Δ angle); ``>`` ascends
   ``*``   a big dot (the symbols in ``dot``), ``dot_size`` times the line width, in
           palette colour ``dot_color``
   ``_``   place the turtle (the explorer's root marker; nothing to do here)
   ======  ==============================================================

   Other symbols are ignored when drawing (they are non-terminals).  Each segment's
   colour index is ``color_start + color_increment * (generation + ;-count)`` into the
   palette, and its width ``width * width_factor**generation`` plus the ``#``/``!``
   changes — the per-iteration colour and width changes of L-Studio (seed 003 §5.10).
3. :func:`draw_segments` rasterises segments (anti-aliased, round caps) fitted into the
   image, or, with ``tileable=True``, scattered over a wrap-around tile so it repeats
   seamlessly.  :func:`lsystem_texture` runs all three.

Already-derived geometry (for example from :mod:`sylva.turtle`) can be drawn by building
:class:`Segments` directly.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from ..errors import GrowthLimitError, SylvaError
from . import _raster
from .colormap import parse_color, to_uint8

__all__ = [
    "LSYSTEM_EXAMPLES",
    "LSystemTextureError",
    "Segments",
    "draw_segments",
    "lsystem_texture",
    "rewrite",
    "turtle",
]


class LSystemTextureError(SylvaError, ValueError):
    """Invalid L-system texture input (bad rule, unbalanced brackets, bad palette …)."""


DEFAULT_PALETTE = ("#4a2f1b", "#5b3a1f", "#2f5d1e", "#3f7a25", "#5d9b35", "#8cc152",
                   "#c2e07a")


def _rules(rules: Mapping) -> dict[str, list[tuple[float, str]]]:
    out = {}
    for pred, succ in rules.items():
        if not isinstance(pred, str) or len(pred) != 1:
            raise LSystemTextureError(f"rule predecessors are single characters, got {pred!r}")
        if isinstance(succ, str):
            out[pred] = [(1.0, succ)]
            continue
        alts = [(float(p), str(s)) for p, s in succ]
        total = sum(p for p, _ in alts)
        if not alts or any(p < 0 for p, _ in alts) or not math.isclose(total, 1.0,
                                                                         abs_tol=1e-9):
            raise LSystemTextureError(
                f"stochastic rule for {pred!r} needs probabilities >= 0 summing to 1, "
                f"got {[p for p, _ in alts]}"
            )
        out[pred] = alts
    for pred, alts in out.items():
        for _, s in alts:
            depth = 0
            for ch in s:
                depth += (ch == "[") - (ch == "]")
                if depth < 0:
                    break
            if depth != 0:
                raise LSystemTextureError(f"successor {s!r} of {pred!r} has unbalanced brackets")
    return out


def _bracket_mask(s: str) -> np.ndarray:
    """For each character of ``s``: is it inside a bracket pair of ``s`` itself?"""
    mask = np.zeros(len(s), dtype=bool)
    depth = 0
    for i, ch in enumerate(s):
        if ch == "[":
            depth += 1
        mask[i] = depth > 0
        if ch == "]":
            depth -= 1
    return mask


def rewrite(axiom: str, rules: Mapping, iterations: int, *, seed: int | None = None,
            max_length: int = 20_000_000) -> tuple[str, np.ndarray]:
    """Derive ``iterations`` parallel rewriting steps.

    Parameters
    ----------
    axiom : str
    rules : mapping of str to str or to a list of (probability, str)
    iterations : int, >= 0
    seed : int, optional
        Seeds the choices of stochastic rules.
    max_length : int
        Limit on the derived string; passing it raises :class:`~sylva.errors.GrowthLimitError`.

    Returns
    -------
    word : str
    generation : ndarray, int16, shape (len(word),)
        The generation of each symbol (see the module notes).

    Examples
    --------
    >>> rewrite("F", {"F": "F[+F]F"}, 2)[0]
    'F[+F]F[+F[+F]F]F[+F]F'
    """
    if int(iterations) != iterations or iterations < 0:
        raise LSystemTextureError(f"iterations must be a whole number >= 0, got {iterations}")
    if not axiom:
        raise LSystemTextureError("the axiom must not be empty")
    table = _rules(rules)
    rng = np.random.default_rng(0 if seed is None else seed)
    # per rule alternative: its text and which of its symbols start a new generation
    comp = {p: [(prob, s, _bracket_mask(s)) for prob, s in alts] for p, alts in table.items()}
    word = axiom
    gen = np.zeros(len(axiom), dtype=np.int16)
    for step in range(1, int(iterations) + 1):
        parts: list[str] = []
        gens: list[np.ndarray] = []
        length = 0
        for ch, g in zip(word, gen):
            alts = comp.get(ch)
            if alts is None:
                parts.append(ch)
                gens.append(np.array([g], dtype=np.int16))
                length += 1
                continue
            if len(alts) == 1:
                _, s, m = alts[0]
            else:
                r = rng.random()
                acc = 0.0
                s, m = alts[-1][1], alts[-1][2]
                for prob, ss, mm in alts:
                    acc += prob
                    if r < acc:
                        s, m = ss, mm
                        break
            parts.append(s)
            gens.append(np.where(m, step, g).astype(np.int16))
            length += len(s)
            if length > max_length:
                raise GrowthLimitError(
                    f"step {step} would pass max_length={max_length} symbols",
                    word=word, step=step - 1)
        word = "".join(parts)
        gen = np.concatenate(gens) if gens else np.zeros(0, dtype=np.int16)
    return word, gen


@dataclass(frozen=True)
class Segments:
    """Line segments in turtle space (y up).

    Attributes
    ----------
    start, end : ndarray, float64, shape (n, 2)
    width : ndarray, float64, shape (n,)
        Line width in pixels.
    color : ndarray, int32, shape (n,)
        Palette index (taken modulo the palette length when drawn).
    generation : ndarray, int16, shape (n,)
    """

    start: np.ndarray
    end: np.ndarray
    width: np.ndarray
    color: np.ndarray
    generation: np.ndarray

    def __len__(self) -> int:
        return int(self.start.shape[0])

    def bounds(self) -> tuple[float, float, float, float]:
        """``(xmin, xmax, ymin, ymax)`` of the segment end points."""
        if len(self) == 0:
            return (0.0, 0.0, 0.0, 0.0)
        pts = np.concatenate([self.start, self.end])
        return (float(pts[:, 0].min()), float(pts[:, 0].max()), float(pts[:, 1].min()),
                float(pts[:, 1].max()))

    def total_length(self) -> float:
        """Sum of the segment lengths."""
        return float(np.linalg.norm(self.end - self.start, axis=1).sum())


def turtle(word: str, angle: float, *, generation=None, step: float = 1.0,
           start_angle: float = 90.0, draw: str = "F", move: str = "fG", width: float = 2.0,
           width_factor: float = 1.0, width_increment: float = 0.0, color_start: int = 0,
           color_increment: int = 1, random_step: tuple[float, float] = (0.5, 1.5),
           step_scale: float = 1.0, angle_scale: float = 1.0, dot: str = "",
           dot_size: float = 3.0, dot_color: int | None = None,
           seed: int | None = None) -> Segments:
    """Interpret ``word`` with a 2D turtle (see the module notes for the commands).

    Parameters
    ----------
    word : str
    angle : float
        Turn angle in degrees (negative allowed).
    generation : array of int, optional
        Per-symbol generations from :func:`rewrite` (default: all 0).
    step : float
        Forward step length.
    start_angle : float
        Initial heading in degrees, counter-clockwise from +x (90 = up).
    draw, move : str
        Symbols that draw, and that move without drawing.
    width, width_factor, width_increment : float
        Initial width in pixels; factor per generation; ``#``/``!`` change.
    color_start, color_increment : int
        Palette index of generation 0 and the change per generation (and per ``;``).
    random_step : (float, float)
        Range of the factor of an ``R`` step.
    step_scale, angle_scale : float
        Factors of the step and the angle per ``<`` level (WWW L-System Explorer's Δ step
        30 % is ``step_scale=0.7``).
    dot, dot_size, dot_color : str, float, int or None
        Symbols drawn as dots, their diameter in line widths, their palette index (None:
        the colour a segment would have there).
    seed : int, optional
        Seed of the ``R`` lengths (``default_rng``; None means 0).

    Examples
    --------
    >>> s = turtle("F+F", 90)
    >>> s.end.round(6).tolist()
    [[0.0, 1.0], [-1.0, 1.0]]
    """
    n = len(word)
    gens = np.zeros(n, dtype=np.int16) if generation is None else np.asarray(generation)
    if gens.shape[0] != n:
        raise LSystemTextureError("generation must have one entry per symbol")
    x = y = 0.0
    head = math.radians(start_angle)
    turn = math.radians(angle)
    cur_step = step
    wdelta = 0.0
    cdelta = 0
    lo, hi = (float(v) for v in random_step)
    if not (0.0 <= lo <= hi):
        raise LSystemTextureError(f"random_step must be a range 0 <= lo <= hi, got {random_step}")
    rng = np.random.default_rng(0 if seed is None else seed)
    stack: list[tuple] = []
    sx: list[float] = []
    sy: list[float] = []
    ex: list[float] = []
    ey: list[float] = []
    ws: list[float] = []
    cs: list[int] = []
    gs: list[int] = []
    count = 0
    for i, ch in enumerate(word):
        if ch.isdigit():
            count = count * 10 + int(ch)
            continue
        reps = count or 1
        count = 0
        if ch in draw or ch in move or ch == "B" or ch == "R":
            sign = -1.0 if ch == "B" else 1.0
            for _ in range(reps):
                length = cur_step * (rng.uniform(lo, hi) if ch == "R" else 1.0)
                nx = x + sign * length * math.cos(head)
                ny = y + sign * length * math.sin(head)
                if ch not in "BR" and ch in move and ch not in draw:
                    x, y = nx, ny
                    continue
                g = int(gens[i])
                sx.append(x)
                sy.append(y)
                ex.append(nx)
                ey.append(ny)
                ws.append(max(width * width_factor**g + wdelta, 0.25))
                cs.append(color_start + color_increment * (g + cdelta))
                gs.append(g)
                x, y = nx, ny
        elif ch in dot:
            g = int(gens[i])
            sx.append(x)
            sy.append(y)
            ex.append(x)
            ey.append(y)
            ws.append(max(dot_size * (width * width_factor**g + wdelta), 0.25))
            cs.append(color_start + color_increment * (g + cdelta) if dot_color is None
                      else int(dot_color))
            gs.append(g)
        elif ch == "+":
            head += turn * reps
        elif ch == "-":
            head -= turn * reps
        elif ch == "|":
            head += math.pi
        elif ch == "<":
            cur_step *= step_scale
            turn *= angle_scale
        elif ch == ">":
            if step_scale != 0.0 and angle_scale != 0.0:
                cur_step /= step_scale
                turn /= angle_scale
        elif ch == "[":
            stack.append((x, y, head, wdelta, cdelta, cur_step, turn))
        elif ch == "]":
            if not stack:
                raise LSystemTextureError(f"unbalanced ']' at position {i} of the word")
            x, y, head, wdelta, cdelta, cur_step, turn = stack.pop()
        elif ch == "#":
            wdelta += width_increment
        elif ch == "!":
            wdelta -= width_increment
        elif ch == ";":
            cdelta += 1
    return Segments(np.column_stack([sx, sy]).reshape(-1, 2),
                    np.column_stack([ex, ey]).reshape(-1, 2),
                    np.asarray(ws, dtype=np.float64), np.asarray(cs, dtype=np.int32),
                    np.asarray(gs, dtype=np.int16))


def _palette(palette) -> np.ndarray:
    cols = [parse_color(c) for c in palette]
    if not cols:
        raise LSystemTextureError("the palette needs at least one colour")
    return np.asarray(cols, dtype=np.float64)


def draw_segments(shape, segments: Segments, *, palette: Sequence = DEFAULT_PALETTE,
                  background="#000000", tileable: bool = False, count: int = 1,
                  size: float = 0.9, seed: int | None = None, margin: float = 0.05,
                  alpha: bool = False) -> np.ndarray:
    """Rasterise ``segments`` into an image.

    Parameters
    ----------
    shape : (H, W)
    segments : Segments
    palette : sequence of colours
        Indexed by ``segments.color`` modulo its length.
    background : colour or None
    tileable : bool
        ``False``: the drawing is scaled to fit the image (``margin`` around it).
        ``True``: ``count`` copies, each scaled to ``size`` times the image height, are
        placed at seeded random positions with wrap-around, so the image tiles seamlessly.
    count, size, seed : int, float, int
        Tileable layout (``seed`` feeds ``default_rng``; ``None`` means 0).
    alpha : bool
        Return RGBA (uint8, coverage in the alpha channel) instead of RGB.

    Returns
    -------
    ndarray, uint8, shape (H, W, 3) or (H, W, 4)
    """
    shape = tuple(int(s) for s in shape)
    if len(shape) != 2 or min(shape) < 1:
        raise LSystemTextureError(f"shape must be (H, W), got {shape}")
    h, w = shape
    cols = _palette(palette)
    rgb = np.zeros((h, w, 3), dtype=np.float64)
    cover = np.zeros((h, w), dtype=np.float64)
    if len(segments):
        xmin, xmax, ymin, ymax = segments.bounds()
        dx = max(xmax - xmin, 1e-12)
        dy = max(ymax - ymin, 1e-12)
        colors = cols[np.mod(segments.color, len(cols))]
        half = segments.width / 2.0
        if not tileable:
            s = min(w * (1 - 2 * margin) / dx, h * (1 - 2 * margin) / dy)
            ox = (w - s * dx) / 2.0 - s * xmin
            oy = (h - s * dy) / 2.0 + s * ymax
            _raster.draw_segments(rgb, cover, ox + s * segments.start[:, 0],
                                  oy - s * segments.start[:, 1], ox + s * segments.end[:, 0],
                                  oy - s * segments.end[:, 1], half, colors, False)
        else:
            if int(count) < 1:
                raise LSystemTextureError(f"count must be positive, got {count}")
            rng = np.random.default_rng(0 if seed is None else seed)
            s = size * h / max(dx, dy)
            for _ in range(int(count)):
                cx, cy = rng.uniform(0, w), rng.uniform(0, h)
                k = s * rng.uniform(0.8, 1.2)
                ox = cx - k * (xmin + dx / 2.0)
                oy = cy + k * (ymin + dy / 2.0)
                _raster.draw_segments(rgb, cover, ox + k * segments.start[:, 0],
                                      oy - k * segments.start[:, 1],
                                      ox + k * segments.end[:, 0], oy - k * segments.end[:, 1],
                                      half, colors, True)
    if alpha:
        return to_uint8(np.concatenate([rgb, cover[..., None]], axis=-1))
    if background is None:
        return to_uint8(rgb)
    bg = np.asarray(parse_color(background))
    out = rgb + bg[None, None, :] * (1.0 - cover[..., None])
    return to_uint8(out)


def lsystem_texture(shape, axiom: str, rules: Mapping, iterations: int, angle: float, *,
                    seed: int | None = None, start_angle: float = 90.0, draw: str = "F",
                    move: str = "fG", width: float = 2.0, width_factor: float = 1.0,
                    width_increment: float = 0.0, color_start: int = 0,
                    color_increment: int = 1, palette: Sequence = DEFAULT_PALETTE,
                    background="#000000", tileable: bool = False, count: int = 1,
                    size: float = 0.9, alpha: bool = False,
                    random_step: tuple[float, float] = (0.5, 1.5), step_scale: float = 1.0,
                    angle_scale: float = 1.0, dot: str = "", dot_size: float = 3.0,
                    dot_color: int | None = None) -> np.ndarray:
    """Derive an L-system and draw it: :func:`rewrite`, :func:`turtle`, :func:`draw_segments`.

    ``seed`` drives the stochastic rules, the ``R`` step lengths and the tileable layout.

    Examples
    --------
    >>> ex = LSYSTEM_EXAMPLES["bush"]
    >>> img = lsystem_texture((64, 64), ex["axiom"], ex["rules"], 2, ex["angle"])
    >>> img.shape, img.dtype.name
    ((64, 64, 3), 'uint8')
    """
    word, gen = rewrite(axiom, rules, iterations, seed=seed)
    segs = turtle(word, angle, generation=gen, start_angle=start_angle, draw=draw, move=move,
                  width=width, width_factor=width_factor, width_increment=width_increment,
                  color_start=color_start, color_increment=color_increment,
                  random_step=random_step, step_scale=step_scale, angle_scale=angle_scale,
                  dot=dot, dot_size=dot_size, dot_color=dot_color, seed=seed)
    return draw_segments(shape, segs, palette=palette, background=background,
                         tileable=tileable, count=count, size=size, seed=seed, alpha=alpha)


LSYSTEM_EXAMPLES: dict[str, dict] = {
    "bush": {"axiom": "F", "rules": {"F": "FF+[+F-F-F]-[-F+F+F]"}, "angle": 22.5,
             "iterations": 4, "source": "seed 003 §4.8 ex. 1 (Paul Bourke, L-System bush)"},
    "stochastic": {"axiom": "F", "rules": {"F": [(0.3, "F[+F]F[-F]"), (0.7, "F[+F]F[+F]")]},
                   "angle": 25.7, "iterations": 4,
                   "source": "seed 003 §4.8 ex. 2 (axiom, angle and depth not in the source)"},
    "bracketed": {"axiom": "F[+F[+F]F]F[-F[-F]F]F[+F[+F]F]F[-F]F[+F]F", "rules": {},
                  "angle": 25.0, "iterations": 0,
                  "source": "seed 003 §4.8 ex. 3 (fig. 33 string, drawn directly)"},
    "alga": {"axiom": "F",
             "rules": {"G": "FF[+FF[+FFF[-FFF]FF]FF]", "A": "FF[-FFF]FFF[-FF[+FFF[-FFF]FF]FFF]",
                       "F": "G[-G[-GG]]G[+GG[-G[-A[+AA]G]A]F[-G]A]FF"},
             "angle": 25.0, "iterations": 3, "start_angle": 90.0, "draw": "FGA", "move": "f",
             "source": "seed 003 §4.8 ex. 4 (Lindenmayer System Generator 'alga')"},
    "lse-bush": {"axiom": "F",
                 "rules": {"A": "FF[-FFF]FFF[-FF[+FFF[-FFF]FF]FFF]",
                           "G": "FF[+FF[+FFF[-FFF]FF]FF]",
                           "F": "FG[-G[-GG]]G[+GG[-G[-A[+AA]G]A]F[-G]A]FF"},
                 "angle": 25.0, "iterations": 3, "draw": "FGA", "move": "f",
                 "source": "seed 003 §4.8 ex. 5 (L-Systems Explorer plant A)"},
    "meadow": {"axiom": "F",
               "rules": {"B": "+[3+F]", "F": "|[3+F][3-F]-|[4+F][6-F]+|[3-F][4-F]B-|F"},
               "angle": 8.0, "iterations": 4, "draw": "F", "move": "f",
               "source": "seed 003 §4.8 ex. 6 (L-Systems Explorer plant B; '|' as in that "
                         "tool draws a plain line, here mapped to 'I')"},
    "lilac": {"axiom": "_*", "rules": {"*": "[+RR<*>][RRRR<*>][-RR<*>]"}, "angle": 30.0,
              "iterations": 7, "step_scale": 0.7, "angle_scale": 0.9, "dot": "*",
              "dot_size": 2.5, "dot_color": 7, "width": 2.0, "seed": 60,
              "palette": ["#4a2f1b", "#5b3a1f", "#6a4a26", "#5c6630", "#4f7a2e", "#5d9b35",
                          "#7bb342", "#b57edc"],
              "background": "#f4f1e8",
              "source": "seed 003 §4.8 ex. 7 (WWW L-System Explorer lilac bush, fig. 60: step "
                        "30, Δ step 30 %, Δ angle 10 %; R steps by 0.5-1.5 times the step)"},
    "koch": {"axiom": "F--F--F", "rules": {"F": "F+F--F+F"}, "angle": 60.0, "iterations": 4,
             "start_angle": 0.0, "source": "seed 003 §4.6 (Koch snowflake)"},
}
"""Example L-systems from seed 003 (axiom, rules, angle, iterations, turtle options)."""

# L-Systems Explorer's '|' draws a non-recursive line; our '|' turns around, so map it to 'I'
_meadow = LSYSTEM_EXAMPLES["meadow"]
_meadow["rules"] = {k: v.replace("|", "I") for k, v in _meadow["rules"].items()}
_meadow["draw"] = "I"
