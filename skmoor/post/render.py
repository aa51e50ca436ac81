"""Off-screen pictures and animations of a run with pyvista (no display needed).

Lines are drawn as tubes coloured by tension on one colour range for the whole run,
the body as its box, the network's free points (line junctions, clump weights, buoys) as
dark spheres where they are at each frame (:func:`point_radii`: a point with mass is drawn
larger, up to twice the size for the heaviest), the sea bed at -depth and a translucent
water surface at z = 0, or moving with the waves (``surface=sea.elevation``). The solver never imports this module.
"""
from __future__ import annotations

import os
from pathlib import Path
from typing import NamedTuple

import matplotlib
import numpy as np

os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
import pyvista as pv  # noqa: E402
from tqdm import tqdm  # noqa: E402
from vtkmodules.vtkCommonCore import VTK_FONT_FILE  # noqa: E402

from .export import (  # noqa: E402
    BOX_FACES,
    _check_index,
    _check_mode,
    box_points,
    has_box,
    mode_scale,
)

pv.OFF_SCREEN = True


class View(NamedTuple):
    """A camera preset: direction from the scene's centre to the camera, view-up vector,
    parallel projection, opacity of the water surface (0: outline only)."""
    direction: tuple
    up: tuple
    parallel: bool
    water: float


CAMERAS = {
    "iso": View((1.0, -1.6, 0.9), (0, 0, 1), False, 0.2),
    "side": View((0, -1, 0), (0, 0, 1), True, 0.2),    # looking along +y: x right, z up
    "front": View((1, 0, 0), (0, 0, 1), True, 0.2),    # looking along -x: y right, z up
    "top": View((0, 0, 1), (0, 1, 0), True, 0.0),      # looking down: x right, y up
}
WINDOW_SIZE = (1024, 768)
CMAP = "plasma"
# VTK's own sans-serif font draws [ ] as ( ): use DejaVu Sans, shipped with matplotlib
FONT = str(Path(matplotlib.get_data_path()) / "fonts" / "ttf" / "DejaVuSans.ttf")


POINT_COLOUR = "#262626"


def snapshot(results, i, path, camera="iso", scale=1.0, window_size=WINDOW_SIZE,
             point_radius=None, zoom=1.0, focus=None, colorbar=True, surface=None) -> Path:
    """PNG of sample ``i`` at ``path``; ``scale`` magnifies the displacements.

    point_radius: how the network's points are drawn (see :func:`point_radii`): None (the
    free points at the default size), a number (their base radius, m; 0: none drawn) or
    one radius per point of ``results.point_names`` (m; 0: not drawn). zoom: magnifies
    the view (> 1: closer) about ``focus`` (3,) m, default the scene's centre; the tubes
    and the default spheres are made thinner by the same factor, so they keep their size
    on the picture. colorbar: draw the tension colour bar. surface: the free surface,
    elevation(xy (n, 2), t) -> (n,) m (e.g. ``sea.elevation``), drawn unscaled on the water
    (None: flat). A static state (``static_results``) is labelled "static equilibrium"
    instead of its time."""
    path = _check_suffix(path, (".png",))
    i = _check_index(results, i)
    scene = _RunScene(results, camera, scale, window_size, point_radius, zoom, focus,
                      colorbar, surface)
    try:
        scene.show(i)
        scene.plotter.screenshot(str(path))
    finally:
        scene.plotter.close()
    return path


def animate(results, path, fps=20, every=None, scale=1.0, camera="iso",
            window_size=WINDOW_SIZE, progress=True, point_radius=None, zoom=1.0,
            focus=None, start=0, colorbar=True, surface=None) -> int:
    """MP4 or GIF (by the suffix of ``path``) of every ``every``-th sample from sample
    ``start`` on.

    ``every=None`` picks the step that plays the run in real time at ``fps`` frames
    per second; point_radius, zoom, focus, colorbar and surface (the moving free surface)
    as for :func:`snapshot`. Returns the number of frames."""
    path = _check_suffix(path, (".gif", ".mp4"))
    _check_positive("fps", fps)
    if every is None:
        dt = float(np.median(np.diff(results.t))) if len(results.t) > 1 else 1.0
        every = max(1, round(1.0 / (fps * dt)))
    if int(every) != every or every < 1:
        raise ValueError(f"every must be an integer >= 1, got {every}")
    start = _check_index(results, start) % len(results.t)
    frames = range(start, len(results.t), int(every))
    scene = _RunScene(results, camera, scale, window_size, point_radius, zoom, focus,
                      colorbar, surface)
    return _record(scene, frames, path, fps, progress)


def animate_mode(points, cells, shape, period, path, n_frames=24, scale=None, fps=12,
                 camera="iso", depth=None, window_size=WINDOW_SIZE, progress=True) -> int:
    """GIF or MP4 of one period (s) of a mode shape (nnodes, 3) of lines with reference
    ``points`` (nnodes, 3) m and ``cells`` (nel, 2); tubes coloured by the local mode
    amplitude. ``scale=None``: largest displacement 5 % of the model's size. The sea
    bed is drawn at -depth (m), by default at the lowest point. Returns n_frames."""
    points, cells, shape = _check_mode(points, cells, shape, period, n_frames)
    path = _check_suffix(path, (".gif", ".mp4"))
    _check_positive("fps", fps)
    scale = mode_scale(points, shape) if scale is None else float(scale)
    scene = _ModeScene(points, cells, shape, period, n_frames, scale, camera, depth, window_size)
    return _record(scene, range(n_frames), path, fps, progress)


def point_radii(results, base=None, masses=None) -> np.ndarray:
    """(npoints,) radius (m) each point of ``results.point_names`` is drawn with: 0 (not
    drawn) for the fixed, coupled and body points; for a free point ``base`` times
    1 + (m / m_max)^(1/3), m its mass (kg) and m_max the heaviest free point's, so a point
    without mass is drawn at ``base`` and the heaviest at twice that. masses: one per
    point (kg), default ``results.meta["point_masses"]`` when the run has them, else all
    zero (results do not carry the points' masses: pass them, or set that key). base:
    default twice the tube radius of the lines (1 % of the lines' extent); 0: none."""
    n = len(results.point_names)
    kinds = list(results.meta.get("point_kinds", []))
    if len(kinds) != n:  # results without the network's point kinds: draw nothing
        return np.zeros(n)
    free = np.array([kind == "free" for kind in kinds], bool)
    if base is None:
        base = 2 * _tube_radius(np.asarray(results.points))
    base = float(base)
    if not (np.isfinite(base) and base >= 0):
        raise ValueError(f"point radius must be a number >= 0 m, got {base}")
    masses = results.meta.get("point_masses") if masses is None else masses
    masses = np.zeros(n) if masses is None else np.asarray(masses, float)
    if masses.shape != (n,) or not np.all(np.isfinite(masses)) or np.any(masses < 0):
        raise ValueError(f"point masses: need {n} finite numbers >= 0 kg, got {masses!r}")
    heaviest = masses[free].max(initial=0.0)
    growth = np.cbrt(masses / heaviest) if heaviest > 0 else np.zeros(n)
    return np.where(free, base * (1 + growth), 0.0)


def default_scale(results, fraction=0.05) -> float:
    """Displacement scale factor that shows the largest node displacement of the run as
    about ``fraction`` of the model's size: 1, or a round 2, 5, 10, 20 ... when the
    motion is smaller than that."""
    points = np.asarray(results.points)
    size = float(np.linalg.norm(np.ptp(points, axis=0)))
    largest = float(np.max(np.linalg.norm(results.displacement, axis=-1), initial=0.0))
    if largest == 0 or largest >= fraction * size:
        return 1.0
    raw = fraction * size / largest
    mag = 10.0 ** np.floor(np.log10(raw))
    return float(mag * max(m for m in (1, 2, 5, 10) if m * mag <= raw))


class _Scene:
    """A plotter with lines as tubes, optional box, sea bed, water and annotations.

    The lines start at ``points`` (nnodes, 3); the bounding box of ``extent`` (n, 3)
    holds every position they will take, to fix the camera."""

    def __init__(self, points, cells, extent, bed_z, bar_title, clim, camera, scale, window_size,
                 box=None, spheres=None, zoom=1.0, focus=None, colorbar=True,
                 water_resolution=10):
        if camera not in CAMERAS:
            raise ValueError(f"camera must be one of {sorted(CAMERAS)}, got {camera!r}")
        _check_positive("zoom", zoom)
        view = CAMERAS[camera]
        lo, hi = extent.min(axis=0), extent.max(axis=0)
        size = float(np.linalg.norm(hi - lo))
        self.radius = _tube_radius(extent) / zoom
        pl = self.plotter = pv.Plotter(off_screen=True, window_size=list(window_size))
        font_scale = (window_size[1] / 768) ** 0.5
        pl.set_background("white", top="#a9cce3")
        # sea bed and water surface over the lines' footprint plus a margin, with outlines
        # that stay visible edge-on
        centre = (lo + hi) / 2
        span = (hi - lo)[:2] + 0.15 * size
        for z, colour, opacity in ((bed_z, "#c2b280", 1.0), (0.0, "#3d85c6", view.water)):
            resolution = 10 if z < 0 else water_resolution
            plane = pv.Plane(center=(centre[0], centre[1], z), i_size=span[0], j_size=span[1],
                             i_resolution=resolution, j_resolution=resolution)
            self.water = plane  # the last one: the water, moved by a free surface
            if opacity > 0:
                pl.add_mesh(plane, color=colour, opacity=opacity, show_edges=bool(z < 0),
                            edge_color="#a89968")
            pl.add_mesh(plane.extract_feature_edges(feature_edges=False, manifold_edges=False),
                        color=colour, line_width=2)

        self.lines = pv.PolyData(points,
                                 lines=np.hstack([np.full((len(cells), 1), 2), cells]))
        self.lines.cell_data["value"] = np.zeros(len(cells))
        self.tubes = self.lines.tube(radius=self.radius)
        lo_bar, hi_bar, n_labels = _nice_range(*clim)
        pl.add_mesh(self.tubes, scalars="value", preference="cell", cmap=CMAP,
                    clim=[lo_bar, hi_bar], smooth_shading=True, ambient=0.3,
                    show_scalar_bar=colorbar,
                    scalar_bar_args=dict(title=bar_title + "\n", color="black", fmt="%.6g",
                                         n_labels=n_labels, vertical=True, position_x=0.86,
                                         position_y=0.25, width=0.06, height=0.5,
                                         title_font_size=round(18 * font_scale),
                                         label_font_size=round(16 * font_scale)))
        for bar in pl.scalar_bars.values():
            _font(bar.GetTitleTextProperty())
            _font(bar.GetLabelTextProperty())
        self.box = None
        if box is not None:
            faces = np.hstack([np.full((6, 1), 4), BOX_FACES]).ravel()
            self.box = pv.PolyData(box, faces)
            pl.add_mesh(self.box, color="#d9d9d9", show_edges=True, edge_color="#404040")
        self.spheres = None  # the spheres' glyphs on self.centres (points with a 'radius')
        if spheres is not None:
            centres, radii = spheres
            self.centres = pv.PolyData(np.asarray(centres, float))
            self.centres.point_data["radius"] = np.asarray(radii, float)
            self.spheres = self._glyphs()
            pl.add_mesh(self.spheres, color=POINT_COLOUR, smooth_shading=True, specular=0.3)
        self.label = pl.add_text("", position="upper_left", font_size=10, color="black",
                                 font_file=FONT)
        if scale != 1:
            pl.add_text(f"displacements x {scale:.3g}", position="lower_right", font_size=8,
                        color="black", font_file=FONT)
        pl.add_axes(color="black")

        pl.camera.focal_point = centre
        pl.camera.position = centre + size * np.asarray(view.direction, dtype=float)
        pl.camera.up = view.up
        if view.parallel:
            pl.enable_parallel_projection()
        pl.reset_camera()
        pl.camera.zoom(1.15 * zoom)
        if focus is not None:  # aim at focus from the same direction and distance
            focus = np.asarray(focus, float)
            if focus.shape != (3,) or not np.all(np.isfinite(focus)):
                raise ValueError(f"focus must be three finite numbers (m), got {focus!r}")
            shift = focus - np.asarray(pl.camera.focal_point)
            pl.camera.position = np.asarray(pl.camera.position) + shift
            pl.camera.focal_point = focus
        pl.camera.SetWindowCenter(0.1, 0.0)   # shift the scene left, away from the bar

    def _glyphs(self):
        return self.centres.glyph(scale="radius", orient=False, geom=pv.Sphere(
            radius=1.0, theta_resolution=24, phi_resolution=16))

    def set(self, positions, values, text, box=None, centres=None):
        """Move the lines (and the box, and the spheres' centres) and set the tube colours
        and the label."""
        self.lines.points = positions
        self.lines.cell_data["value"] = values
        self.tubes.copy_from(self.lines.tube(radius=self.radius))
        if box is not None:
            self.box.points = box
        if centres is not None and self.spheres is not None:
            self.centres.points = np.asarray(centres, float)
            self.spheres.copy_from(self._glyphs())
        self.label.set_text("upper_left", text)


class _RunScene(_Scene):
    """The scene of a run, sample by sample."""

    def __init__(self, results, camera, scale, window_size, point_radius=None, zoom=1.0,
                 focus=None, colorbar=True, surface=None):
        _check_positive("scale", scale)
        _check_positive("zoom", zoom)
        if surface is not None and not callable(surface):
            raise ValueError(f"surface: need a function elevation(xy, t) -> m, got {surface!r}")
        self.results, self.scale, self.surface = results, float(scale), surface
        points, u = np.asarray(results.points), np.asarray(results.displacement)
        extent = np.vstack([points + self.scale * u.min(axis=0),
                            points + self.scale * u.max(axis=0)])
        clim = [np.min(results.tension) / 1e3, np.max(results.tension) / 1e3]
        box = box_points(results, 0, scale) if has_box(results) else None
        if point_radius is None:  # the default base radius, as thin as the tubes on screen
            point_radius = 2 * _tube_radius(extent) / zoom
        radii = _radii(results, point_radius)
        self.drawn = np.flatnonzero(radii > 0)  # the points drawn as spheres
        spheres = ((self._centres(0), radii[self.drawn]) if len(self.drawn) else None)
        super().__init__(points, np.asarray(results.cells), extent,
                         _bed_z(results.depth, extent), "tension [kN]", clim, camera,
                         self.scale, window_size, box, spheres, zoom, focus, colorbar,
                         10 if surface is None else 80)

    def _centres(self, i):
        r = self.results
        return (r.point_reference[self.drawn]
                + self.scale * np.asarray(r.point_displacement[i])[self.drawn])

    def show(self, i):
        r = self.results
        if self.surface is not None:
            water = self.water.points.copy()
            water[:, 2] = self.surface(water[:, :2], float(r.t[i]))
            self.water.points = water
        self.set(r.points + self.scale * r.displacement[i], r.tension[i] / 1e3,
                 "static equilibrium" if r.meta.get("static") else f"t = {r.t[i]:.1f} s",
                 box_points(r, i, self.scale) if self.box is not None else None,
                 self._centres(i) if len(self.drawn) else None)


class _ModeScene(_Scene):
    """One period of a mode shape of the lines, frame by frame."""

    def __init__(self, points, cells, shape, period, n_frames, scale, camera, depth,
                 window_size):
        self.points, self.n_frames, self.period = points, n_frames, period
        self.u = scale * shape
        amplitude = np.linalg.norm(shape, axis=1)
        self.amplitude = amplitude[cells].mean(axis=1) / amplitude.max()
        extent = np.vstack([points + self.u, points - self.u])
        bed = -float(depth) if depth is not None else float(points[:, 2].min())
        super().__init__(points, cells, extent, bed, "mode amplitude [-]", [0, 1], camera,
                         scale, window_size)

    def show(self, k):
        phase = 2 * np.pi * k / self.n_frames
        self.set(self.points + np.sin(phase) * self.u, self.amplitude,
                 f"mode, period {self.period:.3g} s")


def _record(scene, frames, path, fps, progress):
    pl = scene.plotter
    gif = path.suffix == ".gif"
    images = []
    try:
        if not gif:
            pl.open_movie(str(path), framerate=fps, quality=7)
        for k in tqdm(frames, desc=f"render {path.name}", unit="frame",
                      disable=not progress or len(frames) < 30):
            scene.show(k)
            if gif:
                if images:  # (the first screenshot renders the scene itself)
                    pl.render()
                images.append(pl.screenshot(return_img=True))
            else:
                pl.write_frame()
    finally:
        pl.close()
    if gif:
        write_gif(images, path, fps)
    return len(frames)


def write_gif(images, path, fps):
    """A looping GIF of RGB frames (h, w, 3 uint8) at ``fps``: one 256-colour palette
    for every frame (taken from frames across the run: no flicker between frames) and
    Floyd-Steinberg dithering, so that the colour bar's gradient stays continuous
    instead of falling into bands."""
    from PIL import Image

    frames = [Image.fromarray(np.ascontiguousarray(image[..., :3])) for image in images]
    picked = frames[:: max(1, len(frames) // 8)][:8]  # the palette's sample of the run
    sample = Image.new("RGB", (picked[0].width, picked[0].height * len(picked)))
    for k, frame in enumerate(picked):
        sample.paste(frame, (0, k * frame.height))
    palette = sample.quantize(colors=256, method=Image.Quantize.MEDIANCUT)
    coded = [frame.quantize(palette=palette, dither=Image.Dither.FLOYDSTEINBERG)
             for frame in frames]
    coded[0].save(path, save_all=True, append_images=coded[1:], loop=0,
                  duration=round(1000 / fps), optimize=False)


def _nice_range(lo, hi):
    """Round [lo, hi] outwards to multiples of a round step (1, 2, 2.5 or 5 x 10^k) that
    gives 3 to 8 intervals; returns (lo, hi, number of labels)."""
    if hi - lo < 1e-9 * max(1.0, abs(hi)):
        lo, hi = lo - 1, hi + 1
    raw = (hi - lo) / 6
    mag = 10.0 ** np.floor(np.log10(raw))
    step = mag * min(m for m in (1, 2, 2.5, 5, 10) if m * mag >= raw)
    lo, hi = step * np.floor(lo / step + 1e-9), step * np.ceil(hi / step - 1e-9)
    return lo, hi, int(round((hi - lo) / step)) + 1


def _font(prop):
    prop.SetFontFamily(VTK_FONT_FILE)
    prop.SetFontFile(FONT)
    prop.BoldOff()
    prop.ShadowOff()


def _tube_radius(positions) -> float:
    """Radius of the line tubes, m: 0.5 % of the diagonal of the positions' bounding box."""
    positions = np.asarray(positions, float).reshape(-1, 3)
    return 0.005 * float(np.linalg.norm(np.ptp(positions, axis=0)))


def _radii(results, point_radius):
    """(npoints,) sphere radius per network point from snapshot's ``point_radius``."""
    n = len(results.point_names)
    if point_radius is None or np.ndim(point_radius) == 0:
        return point_radii(results, point_radius)
    radii = np.asarray(point_radius, float)
    if radii.shape != (n,) or not np.all(np.isfinite(radii)) or np.any(radii < 0):
        raise ValueError(f"point radius: need a number or {n} finite radii >= 0 m (one per "
                         f"point), got shape {radii.shape}")
    return radii


def _bed_z(depth, positions):
    return -float(depth) if depth > 0 else float(positions[:, 2].min())


def _check_positive(name, value):
    if not value > 0:
        raise ValueError(f"{name} must be > 0, got {value}")


def _check_suffix(path, suffixes):
    path = Path(path)
    if path.suffix not in suffixes:
        raise ValueError(f"path must end in one of {suffixes}, got {path.name!r}")
    path.parent.mkdir(parents=True, exist_ok=True)
    return path
