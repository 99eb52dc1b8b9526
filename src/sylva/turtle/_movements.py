"""cpfg's tropisms and torques: the turtle's bends of the ``tropism:`` and ``torque:`` lines
of a view file, and of the old ``tropism direction:``.

cpfg has two kinds of bending (``movements.c``, ``interpret.c``; CPFG manual §6.8, §8.1.8).

*Movements*, the view file's ``tropism:`` and ``torque:`` lines, each with a vector ``T_i``
(scaled by its intensity), an angle ``γ_i`` (tropisms only), and an elasticity ``e_i`` that
every branch carries (``@Ts(i, e)`` sets it, ``@Ti`` / ``@Td`` step it).  Before each ``F f
G g`` the tropisms together give the desired direction

    V = Σ e_i cos γ_i T_i + Σ e_i sin γ_i T_i × (H × T_i) / |H × T_i|

(``γ = 0``: orthotropism, toward ``T``; ``γ = 90°``: diatropism, across it) and the frame
turns about ``H × V`` by ``min(|H × V|, 1)`` radians (ABOP §2.3's ``e·|H × T|`` for one
tropism, clipped at a radian as cpfg does).  The torques, ``D = Σ e_j T_j``, then roll the
turtle about its heading: ``U`` turns toward ``D``'s part across the heading, ``P = |D|·(D̂ −
(D̂·H)H)``, by ``min(|U × P|, 1)`` (``rotate_to_vector``; cpfg's up vector is sylva's ``−U``,
and cpfg's rotation takes its up away from ``P``).

The *old* tropism, ``tropism direction: T`` with ``initial elasticity: e`` and
``elasticity increment: d`` (``_`` adds ``d`` to a branch's ``e``, ``_(x)`` sets it), bends
after each move: the heading turns toward ``U`` by the angle of sine ``e(T·U)``, then toward
``L`` by the angle of sine ``e(T·L)`` (``interpret.c``'s ``bend``).

cpfg turns only the heading and then re-derives the up vector from the previous segment's
(``adjust_up_and_left``: rolls since the last segment are undone unless ``@Tf``); sylva turns
the whole frame about the same axis, which is the same frame when no roll came between.
"""

from __future__ import annotations

import math

from numba import njit

# the state slots used here (checked against the kernel's at its import)
S_H = 3
S_L = 6
S_U = 9
S_OLD = 21  # the old tropism's elasticity (the kernel's S_ELAST)
#: The state slots of the movements' elasticities: the engine turtle's yaw, block scale,
#: buffer and last move, which only seed 004's executor uses (it bends nothing).
MOV_SLOTS = (20, 22, 23, 24)
MAX_MOVEMENTS = len(MOV_SLOTS)

# the settings layout (after the kernel's own, from C_NMOV on)
C_NMOV = 37  # how many movements
C_MOV = 38  # each: kind (0 tropism, 1 torque), T (3), cos γ, sin γ, e0, step
MOV_W = 8
NC_MOV = C_MOV + MOV_W * MAX_MOVEMENTS


@njit(cache=True)
def turn_frame(st, kx, ky, kz, ang, first):  # pragma: no cover - compiled
    """Rodrigues: the frame vectors from ``first`` on turn about the unit axis k by ``ang``."""
    c = math.cos(ang)
    s = math.sin(ang)
    for off in range(first, S_U + 3, 3):
        vx = st[off]
        vy = st[off + 1]
        vz = st[off + 2]
        d = (kx * vx + ky * vy + kz * vz) * (1.0 - c)
        st[off] = vx * c + (ky * vz - kz * vy) * s + kx * d
        st[off + 1] = vy * c + (kz * vx - kx * vz) * s + ky * d
        st[off + 2] = vz * c + (kx * vy - ky * vx) * s + kz * d


@njit(cache=True)
def movement_adjust(st, cfg):  # pragma: no cover - compiled
    """cpfg's ``movement_adjust``: the tropisms, then the torques (module docstring)."""
    hx = st[S_H]
    hy = st[S_H + 1]
    hz = st[S_H + 2]
    vx = 0.0
    vy = 0.0
    vz = 0.0
    dx = 0.0
    dy = 0.0
    dz = 0.0
    torque = False
    for k in range(int(cfg[C_NMOV])):
        b = C_MOV + MOV_W * k
        e = st[MOV_SLOTS[k]]
        tx = cfg[b + 1]
        ty = cfg[b + 2]
        tz = cfg[b + 3]
        if cfg[b] != 0.0:  # a torque
            dx += e * tx
            dy += e * ty
            dz += e * tz
            torque = True
            continue
        w = e * cfg[b + 4]
        vx += w * tx
        vy += w * ty
        vz += w * tz
        if cfg[b + 5] != 0.0:
            ax = hy * tz - hz * ty  # H x T
            ay = hz * tx - hx * tz
            az = hx * ty - hy * tx
            m = math.sqrt(ax * ax + ay * ay + az * az)
            if m < 1e-7:  # H along T: cpfg turns about its left vector
                ax = st[S_L]
                ay = st[S_L + 1]
                az = st[S_L + 2]
                m = 1.0
            w = e * cfg[b + 5] / m
            vx += w * (ty * az - tz * ay)  # T x (H x T)
            vy += w * (tz * ax - tx * az)
            vz += w * (tx * ay - ty * ax)
    rx = hy * vz - hz * vy  # H x V
    ry = hz * vx - hx * vz
    rz = hx * vy - hy * vx
    m = math.sqrt(rx * rx + ry * ry + rz * rz)
    if m >= 1e-6:
        turn_frame(st, rx / m, ry / m, rz / m, min(m, 1.0), S_H)
    if not torque or (dx == 0.0 and dy == 0.0 and dz == 0.0):
        return
    size = math.sqrt(dx * dx + dy * dy + dz * dz)
    dx /= size
    dy /= size
    dz /= size
    hx = st[S_H]
    hy = st[S_H + 1]
    hz = st[S_H + 2]
    cx = hy * dz - hz * dy  # H x D
    cy = hz * dx - hx * dz
    cz = hx * dy - hy * dx
    if cx * cx + cy * cy + cz * cz <= 1e-8:
        return
    px = (cy * hz - cz * hy) * size  # (H x D) x H: D across the heading
    py = (cz * hx - cx * hz) * size
    pz = (cx * hy - cy * hx) * size
    ux = st[S_U]
    uy = st[S_U + 1]
    uz = st[S_U + 2]
    ax = uy * pz - uz * py  # U x P, along H
    ay = uz * px - ux * pz
    az = ux * py - uy * px
    m = math.sqrt(ax * ax + ay * ay + az * az)
    if m < 1e-7:
        return
    turn_frame(st, ax / m, ay / m, az / m, min(m, 1.0), S_L)  # L and U roll, H stays


@njit(cache=True)
def old_bend(st, tx, ty, tz):  # pragma: no cover - compiled
    """cpfg's ``bend``: the old tropism ``T`` with the branch's elasticity (module docstring)."""
    e = st[S_OLD]
    for side in (S_U, S_L):
        c = e * (tx * st[side] + ty * st[side + 1] + tz * st[side + 2])
        c = max(-1.0, min(1.0, c))
        s = math.sqrt(1.0 - c * c)
        for k in range(3):
            h = st[S_H + k]
            v = st[side + k]
            st[S_H + k] = s * h + c * v
            st[side + k] = s * v - c * h
