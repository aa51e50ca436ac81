"""A small synthetic :class:`skmoor.post.results.Results` for the output tests.

A 26 x 10 x 5 m box moored by 4 lines of 11 elements from its bottom corners to a sea
bed at -100 m. The body surges, heaves and pitches harmonically; each line follows its
fairlead linearly in s; tension grows towards the fairlead and oscillates in time, with
a different phase on each line.
"""
import numpy as np

from skmoor.post.results import Results

DEPTH = 100.0
DRAFT = 0.9
BOX = np.array([26.0, 10.0, 5.0])
NEL = 11
EA = 2e11 * np.pi * 0.05**2
OMEGA = 1.6


def synthetic_results(nt=41, t_end=8.0):
    """Results with ``nt`` samples over [0, t_end] s."""
    t = np.linspace(0.0, t_end, nt)
    center = np.array([0.0, 0.0, BOX[2] / 2 - DRAFT])
    s = np.linspace(0.0, 1.0, NEL + 1)               # 0 at the anchor, 1 at the fairlead
    points, cells, line_of_cell, t_static = [], [], [], []
    for j, (sx, sy) in enumerate([(1, 1), (-1, 1), (-1, -1), (1, -1)]):
        fair = np.array([sx * BOX[0] / 2, sy * BOX[1] / 2, -DRAFT])
        out = np.array([sx * BOX[0], sy * BOX[1], 0.0]) / np.hypot(BOX[0], BOX[1])
        anchor = fair + out * (DEPTH - DRAFT) / np.tan(np.radians(50.0))
        anchor[2] = -DEPTH
        chord = anchor + s[:, None] * (fair - anchor)
        chord[:, 2] -= 4 * np.linalg.norm(fair - anchor) / 60 * s * (1 - s)   # sag
        base = j * (NEL + 1)
        points.append(chord)
        cells.append(base + np.column_stack([np.arange(NEL), np.arange(1, NEL + 1)]))
        line_of_cell.append(np.full(NEL, j))
        t_static.append(4e5 + 1e5 * (s[:-1] + s[1:]) / 2)
    points, cells = np.vstack(points), np.vstack(cells)
    line_of_cell, t_static = np.concatenate(line_of_cell), np.concatenate(t_static)

    wt = OMEGA * t
    body = np.zeros((nt, 6))
    body[:, 0] = 2.0 * np.sin(wt)
    body[:, 2] = 0.3 * np.sin(wt + 0.5)
    body[:, 4] = 0.02 * np.sin(wt + 1.0)
    dbody = np.gradient(body, t, axis=0)
    frac = np.tile(s, 4)                             # node's share of its fairlead motion
    fair_of_node = np.repeat(points[NEL::NEL + 1], NEL + 1, axis=0)
    rel = fair_of_node - center
    disp = np.empty((nt, len(points), 3))
    vel = np.empty_like(disp)
    for i in range(nt):
        rx, ry, rz = body[i, 3:]
        # small rotation: fairlead moves by u + theta x r
        theta = np.array([rx, ry, rz])
        disp[i] = frac[:, None] * (body[i, :3] + np.cross(theta, rel))
        vel[i] = frac[:, None] * (dbody[i, :3] + np.cross(dbody[i, 3:], rel))
    phase = line_of_cell * np.pi / 2
    tension = t_static * (1 + 0.5 * np.sin(wt[:, None] + phase))
    strain = (tension - t_static) / EA
    last = np.arange(4) * NEL + NEL - 1
    return Results(
        t=t, body=body, points=points, cells=cells, line_of_cell=line_of_cell,
        line_names=[f"line{j + 1}" for j in range(4)],
        displacement=disp, velocity=vel, tension=tension, strain=strain,
        fairlead_tension=tension[:, last], anchor_tension=tension[:, last - NEL + 1],
        body_center=center, body_box=BOX.copy(), body_box_center=np.zeros(3),
        depth=DEPTH, meta={"case": "synthetic"},
    )
