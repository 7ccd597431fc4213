#!/usr/bin/env python3
"""dsdem render for a 3D run (summary.json "dimension": 3, tetrahedra in the field frames).

Called by render_fields.py, with its options, when OUT holds a 3D run. For each chosen frame:

  OUT/render/<field>_NNNNNN.png          the model's outer surface in perspective, lit, coloured
                                         by the field
  OUT/render/<field>_section_NNNNNN.png  the model cut by a vertical plane through its centre
                                         (normal y unless --section says otherwise): the half
                                         behind the plane, its cut face showing the field inside

and with --movie OUT/render/<field>.mp4 and <field>_section.mp4. Colour limits and the camera
are fixed over every frame of the series, as in 2D, so a movie neither flickers nor jumps. Each
PNG carries the frame's time ("dsdem:time") and, for the section, the plane ("dsdem:section")
in text chunks.

Drawn by VTK (Debian: python3-vtk9) offscreen. Debian's VTK 9.1 draws through X only: its render
window is vtkXOpenGLRenderWindow (built without OSMesa or EGL), which opens an X display even to
render offscreen and aborts the process when it cannot. So the display is tried in a child
process first, and without a working one a private Xvfb server (Debian: xvfb) is started for the
time of the rendering; with neither, the error says so and what to install.
"""

from __future__ import annotations

import contextlib
import math
import os
import re
import select
import shutil
import signal
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import dsdem_plotlib as lib  # noqa: E402
import numpy as np  # noqa: E402

try:
    from vtkmodules.util import numpy_support as vnp
    from vtkmodules.vtkCommonCore import vtkDoubleArray, vtkLookupTable, vtkVariant
    from vtkmodules.vtkCommonDataModel import vtkPlane, vtkUnstructuredGrid
    from vtkmodules.vtkFiltersCore import vtkCleanPolyData, vtkCutter, vtkFeatureEdges
    from vtkmodules.vtkFiltersGeneral import vtkTableBasedClipDataSet
    from vtkmodules.vtkFiltersGeometry import vtkDataSetSurfaceFilter
    from vtkmodules.vtkIOImage import vtkPNGWriter
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
    from vtkmodules.vtkRenderingAnnotation import vtkCubeAxesActor, vtkScalarBarActor
    from vtkmodules.vtkRenderingCore import (
        vtkActor,
        vtkLightKit,
        vtkPolyDataMapper,
        vtkRenderer,
        vtkRenderWindow,
        vtkTextActor,
        vtkWindowToImageFilter,
    )
    import vtkmodules.vtkRenderingFreeType  # noqa: F401  (text)
    import vtkmodules.vtkRenderingOpenGL2  # noqa: F401  (the render window's factory)
except ImportError as e:  # pragma: no cover
    lib.fail(f"rendering a 3D run needs VTK's Python bindings (Debian: apt install python3-vtk9): {e}", 1)


class RenderUnavailable(Exception):
    """No way to draw offscreen here: exit code 1 with the reason (not bad input)."""


FIELD_ALIASES = {
    **lib.FIELD_ALIASES,
    "szz": "stress_Pa:zz",
    "syz": "stress_Pa:yz",
    "sxz": "stress_Pa:xz",
}
PRETTY = {
    "velocity_m_per_s": "Velocity magnitude",
    "displacement_m": "Displacement magnitude",
    "acceleration_m_per_s2": "Acceleration magnitude",
    "von_mises_stress_Pa": "Von Mises stress",
    "max_principal_stress_Pa": "Max principal stress",
    "min_principal_stress_Pa": "Min principal stress",
    "material_id": "Material",
    "group_id": "Physical group",
}
VECTOR_COMPONENTS = {"x": 0, "y": 1, "z": 2}
AXES = {"x": 0, "y": 1, "z": 2}
VALUE = "dsdem_value"  # the array drawn: the field's values, scaled to the colour bar's unit


# ------------------------------------------------------------------------------------
# The display VTK draws on
# ------------------------------------------------------------------------------------

_PROBE = (
    "from vtkmodules.vtkRenderingCore import vtkRenderWindow\n"
    "import vtkmodules.vtkRenderingOpenGL2\n"
    "w = vtkRenderWindow()\nw.SetOffScreenRendering(1)\nw.SetSize(8, 8)\nw.Render()\n"
)


def _probe(env: dict) -> tuple[bool, str]:
    """Whether VTK can render offscreen with this environment: tried in a child process, since a
    failed X connection aborts the process that tries it."""
    try:
        r = subprocess.run([sys.executable, "-c", _PROBE], env=env, capture_output=True, text=True, timeout=60)
    except (OSError, subprocess.TimeoutExpired) as e:
        return False, str(e)
    lines = [ln for ln in r.stderr.splitlines() if ln.strip()]
    return r.returncode == 0, (lines[-1] if lines else f"exit code {r.returncode}")


def _die_with_parent() -> None:
    """In the Xvfb child: terminate when the renderer dies, even killed outright."""
    try:
        import ctypes

        ctypes.CDLL(None, use_errno=True).prctl(1, signal.SIGTERM)  # PR_SET_PDEATHSIG
    except Exception:  # noqa: BLE001 - best effort; the normal path stops it anyway
        pass


def _start_xvfb(xvfb: str) -> tuple[subprocess.Popen, str]:
    """A private X server on a free display number (Xvfb picks it and writes it to a pipe)."""
    rfd, wfd = os.pipe()
    try:
        proc = subprocess.Popen(
            [xvfb, "-displayfd", str(wfd), "-screen", "0", "1920x1200x24", "-nolisten", "tcp", "-noreset"],
            pass_fds=[wfd], stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
            preexec_fn=_die_with_parent,
        )
    finally:
        os.close(wfd)
    buf = b""
    try:
        while not buf.endswith(b"\n"):
            ready, _, _ = select.select([rfd], [], [], 20.0)
            if not ready:
                break
            chunk = os.read(rfd, 64)
            if not chunk:
                break
            buf += chunk
    finally:
        os.close(rfd)
    number = buf.decode(errors="replace").strip()
    if not number.isdigit():
        proc.kill()
        err = proc.communicate()[1].decode(errors="replace").strip().splitlines()
        raise RenderUnavailable(f"Xvfb did not start ({err[-1] if err else 'no display number'})")
    return proc, f":{number}"


@contextlib.contextmanager
def offscreen_display():
    """Makes sure VTK can render offscreen for the duration: the current DISPLAY if it works,
    else a private Xvfb server. Raises RenderUnavailable with the reason otherwise."""
    if vtkRenderWindow().GetClassName() != "vtkXOpenGLRenderWindow":  # an OSMesa or EGL build: no X
        yield
        return
    current = os.environ.get("DISPLAY", "")
    if current:
        ok, why = _probe(dict(os.environ))
        if ok:
            yield
            return
        reason = f"the X display DISPLAY={current} does not work ({why})"
    else:
        reason = "there is no X display (DISPLAY is not set)"
    explain = ("this VTK renders through X only (vtkXOpenGLRenderWindow: Debian's VTK 9.1 is built without "
               "OSMesa or EGL), so even offscreen rendering needs an X server")
    xvfb = shutil.which("Xvfb")
    if xvfb is None:
        raise RenderUnavailable(f"cannot render the 3D run: {reason}, and {explain}. Install xvfb "
                                "(scripts/install-deps.sh; Debian: apt install xvfb) or run under an X display")
    proc, display = _start_xvfb(xvfb)
    try:
        os.environ["DISPLAY"] = display
        ok, why = _probe(dict(os.environ))
        if not ok:
            raise RenderUnavailable(f"cannot render the 3D run: {reason}, and VTK cannot draw on the private "
                                    f"Xvfb display {display} either ({why}); {explain}")
        yield
    finally:
        if current:
            os.environ["DISPLAY"] = current
        else:
            os.environ.pop("DISPLAY", None)
        proc.terminate()
        try:
            proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()


# ------------------------------------------------------------------------------------
# Frames and fields
# ------------------------------------------------------------------------------------


def read_grid(path: Path) -> vtkUnstructuredGrid:
    rd = vtkXMLUnstructuredGridReader()
    rd.SetFileName(str(path))
    rd.Update()
    out = rd.GetOutput()
    if out is None or out.GetNumberOfPoints() == 0 or out.GetNumberOfCells() == 0:
        raise lib.InputError(f"{path}: cannot read (not a VTK unstructured grid with cells)")
    grid = vtkUnstructuredGrid()
    grid.ShallowCopy(out)
    return grid


def grid_time(grid, fallback: float) -> float:
    if math.isfinite(fallback):
        return fallback
    tv = grid.GetFieldData().GetArray("TimeValue")
    return float(tv.GetTuple1(0)) if tv is not None and tv.GetNumberOfTuples() else math.nan


def _arrays(data) -> dict:
    """name -> (components, component names, integer?) of a point or cell data set."""
    out = {}
    for i in range(data.GetNumberOfArrays()):
        a = data.GetArray(i)
        if a is None or a.GetName() in (None, VALUE):
            continue
        n = a.GetNumberOfComponents()
        names = [a.GetComponentName(k) or "" for k in range(n)]
        out[a.GetName()] = (n, names, a.GetDataTypeAsString() in ("int", "long", "long long", "short", "char",
                                                                  "signed char", "unsigned char", "unsigned int",
                                                                  "idtype", "vtkIdType", "unsigned long"))
    return out


@dataclass
class FieldSpec:
    key: str            # as the user typed it (file names)
    array: str          # VTU array name
    where: str          # "point" | "cell"
    component: int | None
    categorical: bool
    label: str
    unit: str
    signed: bool = False


def resolve_field(key: str, grid) -> FieldSpec:
    point, cell = _arrays(grid.GetPointData()), _arrays(grid.GetCellData())
    avail = sorted(set(point) | set(cell))
    if key == "damage":
        raise lib.InputError(f"--field damage: a 3D run has no joints and no damage; use velocity, displacement, "
                             f"material, stress or one of: {', '.join(avail)}")
    name = FIELD_ALIASES.get(key, key)
    comp_text = None
    if ":" in name:
        name, comp_text = name.split(":", 1)
    where = "point" if name in point else "cell" if name in cell else None
    if where is None:
        raise lib.InputError(
            f"--field {key}: no array '{name}' in the field frames; use velocity, displacement, material, "
            f"stress or one of: {', '.join(avail)}"
        )
    ncomp, comp_names, integer = (point if where == "point" else cell)[name]
    q, unit = lib.split_unit(name)
    comp = None
    if comp_text is not None:
        if comp_text in comp_names:
            comp = comp_names.index(comp_text)
        elif ncomp == 3 and comp_text in VECTOR_COMPONENTS:
            comp = VECTOR_COMPONENTS[comp_text]
        elif comp_text.isdigit() and int(comp_text) < ncomp:
            comp = int(comp_text)
        else:
            choices = [c for c in comp_names if c] or (list(VECTOR_COMPONENTS) if ncomp == 3 else [])
            raise lib.InputError(f"--field {key}: '{name}' has no component '{comp_text}' (it has {ncomp}"
                                 + (f": {', '.join(choices)}" if choices else "") + ")")
    label = PRETTY.get(name) or lib.humanize(q).capitalize()
    if ncomp > 1:
        if comp is not None:
            cname = comp_names[comp] or (("x", "y", "z")[comp] if ncomp == 3 else str(comp))
            label = f"{lib.humanize(q).capitalize()} {cname}"
        elif where == "cell" and not name.startswith(("velocity", "displacement", "acceleration")):
            first = comp_names[0] or "0"
            raise lib.InputError(
                f"--field {key}: '{name}' has {ncomp} components; pick one, e.g. --field {name}:{first}"
            )
        elif name not in PRETTY:
            label = f"{lib.humanize(q).capitalize()} magnitude"
    categorical = integer and ncomp == 1
    signed = comp is not None or "principal" in name
    return FieldSpec(key, name, where, comp, categorical, label, unit, signed)


def field_values(spec: FieldSpec, grid) -> np.ndarray:
    data = grid.GetPointData() if spec.where == "point" else grid.GetCellData()
    a = data.GetArray(spec.array)
    if a is None:
        raise lib.InputError(f"a field frame has no array '{spec.array}' (the run's frames differ)")
    v = vnp.vtk_to_numpy(a).astype(np.float64)
    if v.ndim == 2:
        v = v[:, spec.component] if spec.component is not None else np.linalg.norm(v, axis=1)
    return v.reshape(-1)


@dataclass
class Frame3:
    number: int
    time: float
    grid: vtkUnstructuredGrid
    values: np.ndarray


def parse_section(text: str, bounds: list[float]) -> tuple[int, float]:
    """--section x|y|z[=coordinate in m] -> (axis, coordinate); the model's centre by default."""
    m = re.fullmatch(r"\s*([xyzXYZ])\s*(?:=\s*(\S+))?\s*", text or "y")
    if not m:
        raise lib.InputError(f"--section {text}: expected x, y or z, optionally =COORDINATE in m (e.g. y=10)")
    axis = AXES[m.group(1).lower()]
    lo, hi = bounds[2 * axis], bounds[2 * axis + 1]
    if m.group(2) is None:
        return axis, 0.5 * (lo + hi)
    try:
        c = float(m.group(2))
    except ValueError:
        c = math.nan
    if not math.isfinite(c):
        raise lib.InputError(f"--section {text}: '{m.group(2)}' is not a coordinate in m")
    if not lo < c < hi:
        raise lib.InputError(f"--section {text}: the plane misses the model, which spans "
                             f"{'xyz'[axis]} = {lo:.4g} to {hi:.4g} m")
    return axis, c


# ------------------------------------------------------------------------------------
# Drawing
# ------------------------------------------------------------------------------------


def _lut_from(colors) -> vtkLookupTable:
    lut = vtkLookupTable()
    lut.SetNumberOfTableValues(len(colors))
    for i, c in enumerate(colors):
        lut.SetTableValue(i, float(c[0]), float(c[1]), float(c[2]), 1.0)
    lut.Build()
    return lut


def _text(size: int, color=(0.1, 0.1, 0.1), bold=False):
    t = vtkTextActor()
    p = t.GetTextProperty()
    p.SetFontFamilyToArial()
    p.SetFontSize(size)
    p.SetColor(*color)
    p.SetBold(bold)
    return t


def _view_direction(azimuth_deg: float, elevation_deg: float) -> np.ndarray:
    """Unit vector from the focal point to the camera: azimuth in the xy plane from +x, elevation above it."""
    az, el = math.radians(azimuth_deg), math.radians(elevation_deg)
    return np.array([math.cos(el) * math.cos(az), math.cos(el) * math.sin(az), math.sin(el)])


class View:
    """One picture per frame (perspective of the outer surface, or the section): its window,
    pipeline, colour bar and texts, built once and fed each frame's grid."""

    SCENE = 0.8  # share of the width for the model; the rest holds the colour bar

    def __init__(self, r: "Renderer3D", section: bool):
        self.r, self.section = r, section
        W, H = r.size
        self.win = vtkRenderWindow()
        self.win.SetOffScreenRendering(1)
        self.win.SetSize(W, H)
        self.win.SetMultiSamples(0)  # FXAA instead: as smooth here, and faster than multisampling under Mesa
        self.win.SetNumberOfLayers(2)
        self.scene = vtkRenderer()
        self.scene.SetViewport(0.0, 0.0, self.SCENE, 1.0)
        self.scene.SetBackground(1.0, 1.0, 1.0)
        self.scene.UseFXAAOn()
        side = vtkRenderer()  # white under the colour bar
        side.SetViewport(self.SCENE, 0.0, 1.0, 1.0)
        side.SetBackground(1.0, 1.0, 1.0)
        self.overlay = vtkRenderer()
        self.overlay.SetLayer(1)
        self.overlay.SetViewport(0.0, 0.0, 1.0, 1.0)
        for ren in (self.scene, side, self.overlay):
            self.win.AddRenderer(ren)
        self.scene.AutomaticLightCreationOff()
        vtkLightKit().AddLightsToRenderer(self.scene)

        # The drawn grid: the frame's, or the half of it behind the section plane.
        self.plane = vtkPlane()
        axis, coord = r.section_axis, r.section_coord
        normal = [0.0, 0.0, 0.0]
        normal[axis] = -1.0 if axis == 2 else 1.0  # keep the far side: the camera looks at the cut
        origin = [0.5 * (r.bounds[2 * k] + r.bounds[2 * k + 1]) for k in range(3)]
        origin[axis] = coord
        self.plane.SetOrigin(*origin)
        self.plane.SetNormal(*normal)
        if section:
            self.clip = vtkTableBasedClipDataSet()
            self.clip.SetClipFunction(self.plane)
            self.clip.SetValue(0.0)
            surface_input = self.clip.GetOutputPort()
        self.surface = vtkDataSetSurfaceFilter()
        if section:
            self.surface.SetInputConnection(surface_input)
        mapper = vtkPolyDataMapper()
        mapper.SetInputConnection(self.surface.GetOutputPort())
        mapper.SetResolveCoincidentTopologyToPolygonOffset()  # the edges drawn on the faces stay in front
        self.setup_colours(mapper)
        actor = vtkActor()
        actor.SetMapper(mapper)
        prop = actor.GetProperty()
        # Mostly ambient: the shading shows the shape without greying the colour map's hues away.
        prop.SetAmbient(0.45)
        prop.SetDiffuse(0.6)
        prop.SetSpecular(0.08)
        prop.SetSpecularPower(20)
        if r.show_mesh_edges:  # a small mesh: its triangles help to read the shape
            prop.EdgeVisibilityOn()
            prop.SetEdgeColor(0.25, 0.25, 0.25)
            prop.SetLineWidth(0.6)
        self.scene.AddActor(actor)

        # The model's corners (feature edges) in grey: its shape where colours are alike.
        self.edges = vtkFeatureEdges()
        self.edges.SetInputConnection(self.surface.GetOutputPort())
        self.edges.BoundaryEdgesOn()
        self.edges.FeatureEdgesOn()
        self.edges.SetFeatureAngle(35.0)
        self.edges.ManifoldEdgesOff()
        self.edges.NonManifoldEdgesOff()
        self.edges.ColoringOff()
        em = vtkPolyDataMapper()
        em.SetInputConnection(self.edges.GetOutputPort())
        em.ScalarVisibilityOff()
        ea = vtkActor()
        ea.SetMapper(em)
        ea.GetProperty().SetColor(0.15, 0.15, 0.15)
        ea.GetProperty().SetLineWidth(1.5)
        ea.GetProperty().LightingOff()
        self.scene.AddActor(ea)

        if section:  # the cut's outline, bold
            self.cutter = vtkCutter()
            self.cutter.SetCutFunction(self.plane)
            merged = vtkCleanPolyData()  # one polygon per cut tetrahedron: merged, only the outline is a boundary
            merged.SetInputConnection(self.cutter.GetOutputPort())
            om = vtkPolyDataMapper()
            outline = vtkFeatureEdges()
            outline.SetInputConnection(merged.GetOutputPort())
            outline.BoundaryEdgesOn()
            outline.FeatureEdgesOff()
            outline.ManifoldEdgesOff()
            outline.NonManifoldEdgesOff()
            outline.ColoringOff()
            om.SetInputConnection(outline.GetOutputPort())
            om.ScalarVisibilityOff()
            oa = vtkActor()
            oa.SetMapper(om)
            oa.GetProperty().SetColor(0.0, 0.0, 0.0)
            oa.GetProperty().SetLineWidth(2.5)
            oa.GetProperty().LightingOff()
            # A hair toward the camera (on the side the plane's normal points away from), so the
            # cut face does not hide its own outline.
            diag = math.dist(r.bounds[0::2], r.bounds[1::2])
            oa.SetPosition(*(-2e-3 * diag * np.array(normal)))
            self.scene.AddActor(oa)

        self.place_camera()
        self.add_axes()
        self.add_texts()
        self.grab = vtkWindowToImageFilter()
        self.grab.SetInput(self.win)
        self.grab.SetInputBufferTypeToRGB()
        self.grab.ReadFrontBufferOff()

    # -------------------------------------------------------------- colours
    def setup_colours(self, mapper) -> None:
        r, spec = self.r, self.r.spec
        mapper.SetScalarModeToUsePointFieldData() if spec.where == "point" else mapper.SetScalarModeToUseCellFieldData()
        mapper.SelectColorArray(VALUE)
        mapper.ScalarVisibilityOn()
        if spec.categorical:
            lut = vtkLookupTable()
            names = r.category_names()
            colors = r.category_colors
            lut.SetNumberOfTableValues(len(r.cats))
            lut.IndexedLookupOn()
            for i, (c, col) in enumerate(zip(r.cats, colors)):
                lut.SetTableValue(i, float(col[0]), float(col[1]), float(col[2]), 1.0)
                lut.SetAnnotation(vtkVariant(float(c)), names.get(c, str(c)))
            mapper.SetLookupTable(lut)
            mapper.UseLookupTableScalarRangeOn()
        else:
            lut = _lut_from(r.colormap)
            lut.SetRange(r.lo * r.factor, r.hi * r.factor)
            mapper.SetLookupTable(lut)
            mapper.SetScalarRange(r.lo * r.factor, r.hi * r.factor)
            mapper.InterpolateScalarsBeforeMappingOn()  # point data: the colour map's colours, not blends
        self.lut = lut

    # -------------------------------------------------------------- axes and camera
    def add_axes(self) -> None:
        """Axes along the box drawn (the model's, or the kept half's), labelled in m; the section
        has none along its normal."""
        ax = vtkCubeAxesActor()
        box = list(self.box)
        if self.section and self.r.section_axis != 2:  # in the cut's plane, where the field is read
            box[2 * self.r.section_axis] = box[2 * self.r.section_axis + 1] = self.r.section_coord
        ax.SetBounds(box)
        if self.section:
            k = "XYZ"[self.r.section_axis]
            for what in ("AxisVisibility", "AxisLabelVisibility", "AxisTickVisibility", "AxisMinorTickVisibility"):
                getattr(ax, f"Set{k}{what}")(0)
        ax.SetCamera(self.scene.GetActiveCamera())
        ax.SetFlyModeToOuterEdges()
        ax.SetXTitle("x (m)")
        ax.SetYTitle("y (m)")
        ax.SetZTitle("z (m)")
        scale = self.r.size[0] / 1280.0  # the labels grow with the picture, as the other texts
        ax.SetScreenSize(11.0 * scale)
        ax.SetLabelOffset(14 * scale)
        ax.SetTitleOffset(22 * scale)
        for k in range(3):
            for prop in (ax.GetTitleTextProperty(k), ax.GetLabelTextProperty(k)):
                prop.SetColor(0.25, 0.25, 0.25)
            ax.GetTitleTextProperty(k).SetFontSize(round(14 * scale))
        for prop in (ax.GetXAxesLinesProperty(), ax.GetYAxesLinesProperty(), ax.GetZAxesLinesProperty()):
            prop.SetColor(0.45, 0.45, 0.45)
        ax.DrawXGridlinesOff()
        ax.DrawYGridlinesOff()
        ax.DrawZGridlinesOff()
        ax.SetTickLocationToOutside()
        self.scene.AddActor(ax)

    def place_camera(self) -> None:
        """A fixed camera over every frame: the box of the model (of the kept half for the
        section) filling the scene, seen from the front left, above."""
        r = self.r
        b = list(r.bounds)
        axis = r.section_axis
        if self.section:
            if axis == 2:  # the lower half, seen from above
                b[5] = r.section_coord
                d = _view_direction(-100.0, 60.0)
            else:  # the far half, seen nearly along the normal, a little from the left and above
                b[2 * axis] = r.section_coord
                az = -105.0 if axis == 1 else 195.0
                d = _view_direction(az, 18.0)
        else:
            d = _view_direction(-125.0, 28.0)
        self.box = b
        centre = np.array([0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]), 0.5 * (b[4] + b[5])])
        cam = self.scene.GetActiveCamera()
        cam.SetFocalPoint(*centre)
        cam.SetPosition(*(centre + d))
        cam.SetViewUp(0.0, 0.0, 1.0)
        cam.SetViewAngle(30.0)
        self.scene.ResetCamera(b)
        # ResetCamera fits the box's bounding sphere: zoom until its corners fill 78 % of the scene
        # (the axes' labels take the rest).
        W, H = self.r.size
        aspect = (self.SCENE * W) / H
        m = cam.GetCompositeProjectionTransformMatrix(aspect, -1.0, 1.0)
        M = np.array([[m.GetElement(i, j) for j in range(4)] for i in range(4)])
        corners = np.array([[x, y, z, 1.0] for x in b[0:2] for y in b[2:4] for z in b[4:6]])
        p = corners @ M.T
        ndc = p[:, :2] / p[:, 3:4]
        extent = max(float(np.max(np.abs(ndc[:, 0]))), float(np.max(np.abs(ndc[:, 1]))) / 0.88)
        if extent > 0:
            cam.Zoom(0.78 / extent)
        self.scene.ResetCameraClippingRange(b)

    # -------------------------------------------------------------- texts
    def add_texts(self) -> None:
        r = self.r
        W, H = r.size
        s = W / 1280.0
        self.title = _text(round(19 * s), bold=True)
        self.title.SetDisplayPosition(round(16 * s), H - round(34 * s))
        self.overlay.AddActor2D(self.title)
        run = _text(round(13 * s), color=(0.4, 0.4, 0.4))
        t = r.run_title if len(r.run_title) <= 70 else r.run_title[:67] + "..."
        run.SetInput(t)
        run.GetTextProperty().SetJustificationToRight()
        run.SetDisplayPosition(W - round(16 * s), H - round(30 * s))
        self.overlay.AddActor2D(run)
        self.note = _text(round(13 * s), color=(0.3, 0.3, 0.3))
        self.note.SetDisplayPosition(round(16 * s), round(12 * s))
        self.overlay.AddActor2D(self.note)
        if self.section:
            self.note.SetInput(f"Section {r.section_text}: the model behind the plane, its cut face showing the "
                               "field inside")
        else:
            self.note.SetInput("The model's outer surface (deformed configuration, true scale)")

        bar = vtkScalarBarActor()
        bar.SetLookupTable(self.lut)
        bar.SetTitle(r.bar_title)
        bar.UnconstrainedFontSizeOn()
        bar.GetTitleTextProperty().SetFontSize(round(15 * s))
        bar.GetLabelTextProperty().SetFontSize(round(13 * s))
        for prop in (bar.GetTitleTextProperty(), bar.GetLabelTextProperty(), bar.GetAnnotationTextProperty()):
            prop.SetColor(0.1, 0.1, 0.1)
            prop.SetFontFamilyToArial()
            prop.ShadowOff()
            prop.ItalicOff()
        bar.GetTitleTextProperty().BoldOn()
        bar.GetLabelTextProperty().BoldOff()
        bar.SetBarRatio(0.22)
        bar.SetVerticalTitleSeparation(round(8 * s))
        bar.SetPosition(self.SCENE + 0.015, 0.1)
        bar.SetWidth(0.17)
        bar.SetHeight(0.76)
        if r.spec.categorical:
            bar.DrawAnnotationsOn()
            bar.SetNumberOfLabels(0)
            bar.GetAnnotationTextProperty().SetFontSize(round(13 * s))
        else:
            bar.SetNumberOfLabels(6)
            bar.SetLabelFormat("%.3g")
        self.overlay.AddActor2D(bar)

    # -------------------------------------------------------------- a frame
    def draw(self, fd: Frame3) -> Path:
        r = self.r
        if self.section:
            self.clip.SetInputData(fd.grid)
            self.cutter.SetInputData(fd.grid)
        else:
            self.surface.SetInputData(fd.grid)
        tstr = f"t = {r.tfmt.format(fd.time)} s" if math.isfinite(fd.time) else f"frame {fd.number}"
        self.title.SetInput(f"{r.spec.label}, {tstr}" + (f", section {r.section_text}" if self.section else ""))
        self.win.Render()
        self.grab.Modified()
        self.grab.Update()
        r.render_dir.mkdir(parents=True, exist_ok=True)
        stem = r.safe_key + ("_section" if self.section else "")
        path = r.render_dir / f"{stem}_{fd.number:06d}.png"
        tmp = path.with_name(path.stem + ".tmp.png")
        w = vtkPNGWriter()
        w.SetCompressionLevel(3)
        w.SetInputConnection(self.grab.GetOutputPort())
        w.SetFileName(str(tmp))
        w.AddText("dsdem:time", repr(float(fd.time)))
        if self.section:
            w.AddText("dsdem:section", r.section_text)
        w.Write()
        if not tmp.is_file():
            raise RuntimeError(f"{tmp}: VTK wrote no picture")
        tmp.replace(path)
        return path

    def close(self) -> None:
        self.win.Finalize()


class Renderer3D:
    def __init__(self, args, out: Path, r2):
        self.a, self.out, self.r2 = args, out, r2
        self.render_dir = out / "render"
        self.summary = lib.read_summary(out)
        self.scenario = lib.load_yaml(lib.find_scenario(out, self.summary))
        self.run_title = str(self.summary.get("title") or out.name)

    def log(self, msg: str) -> None:
        if not self.a.quiet:
            print(msg, flush=True)

    def category_names(self) -> dict[int, str]:
        if self.spec.array == "material_id":
            return lib.material_names(self.summary, self.scenario)
        return {}

    def load(self) -> None:
        out, a, r2 = self.out, self.a, self.r2
        frames = lib.read_pvd(out / "fields.pvd") or lib.glob_frames(out / "fields", "fields")
        if not frames:
            raise lib.InputError(f"{out / 'fields.pvd'}: no field frames (was the run made with --no-fields?)")
        selected = r2.select_frames(frames, a.frames)
        wanted = {f.number for f in selected}
        first = read_grid(selected[0].path)
        self.spec = resolve_field(a.field, first)
        self.safe_key = r2.safe_name(self.spec.key)
        lo, hi = math.inf, -math.inf
        cats: set[int] = set()
        bounds = [math.inf, -math.inf] * 3
        start = None  # the first frame's box: where the default section's plane goes
        by_number: dict[int, Frame3] = {}
        self.all_times = []
        # Every frame counts for the colour limits and the camera; only the chosen ones are kept.
        for fr in frames:
            g = first if fr is selected[0] else read_grid(fr.path)
            b = g.GetBounds()
            start = start or list(b)
            for k in range(3):
                bounds[2 * k] = min(bounds[2 * k], b[2 * k])
                bounds[2 * k + 1] = max(bounds[2 * k + 1], b[2 * k + 1])
            v = field_values(self.spec, g)
            fin = v[np.isfinite(v)]
            if fin.size:
                lo, hi = min(lo, float(fin.min())), max(hi, float(fin.max()))
                if self.spec.categorical:
                    cats.update(int(x) for x in np.unique(fin))
            t = grid_time(g, fr.time)
            self.all_times.append(t)
            if fr.number in wanted:
                by_number[fr.number] = Frame3(fr.number, t, g, v)
        self.frames = [by_number[f.number] for f in selected]
        if a.clim:
            lo, hi = r2.parse_floats(a.clim, 2, "--clim")
            if not hi > lo:
                raise lib.InputError(f"--clim {a.clim}: need lo < hi")
        elif not self.spec.categorical:
            if not math.isfinite(lo):
                lo, hi = 0.0, 1.0
            if self.spec.signed and lo < 0 < hi:
                lo, hi = -max(-lo, hi), max(-lo, hi)
            elif not self.spec.signed:
                lo = min(0.0, lo)
            if hi <= lo:
                hi = lo + (abs(lo) if lo != 0 else 1.0) * 1e-6 + 1e-30
        self.lo, self.hi = lo, hi
        self.cats = sorted(cats) or [0]
        if a.bbox:
            v = r2.parse_floats(a.bbox, 6, "--bbox") if a.bbox.count(",") == 5 else None
            if v is None:
                raise lib.InputError(f"--bbox {a.bbox}: a 3D run takes the box xmin,xmax,ymin,ymax,zmin,zmax in m")
            if not (v[1] > v[0] and v[3] > v[2] and v[5] > v[4]):
                raise lib.InputError(f"--bbox {a.bbox}: need xmin < xmax, ymin < ymax and zmin < zmax")
            bounds = v
        self.bounds = bounds
        self.section_axis, self.section_coord = parse_section(getattr(a, "section", None) or "y", start)
        self.section_text = f"{'xyz'[self.section_axis]} = {self.section_coord:.4g} m"

        # Colours as in 2D: turbo, or a diverging map for a signed quantity on both sides of 0.
        import matplotlib

        if self.spec.categorical:
            self.category_colors = r2.category_colors(len(self.cats), without_blue=False)
            self.factor, unit = 1.0, ""
            self.bar_title = self.spec.label
        else:
            self.factor, unit = lib.autoscale(max(abs(self.lo), abs(self.hi)), self.spec.unit)
            name = "RdBu_r" if (self.spec.signed and self.lo < 0 < self.hi) else "turbo"
            self.colormap = matplotlib.colormaps[name](np.linspace(0.0, 1.0, 256))
            self.bar_title = lib.axis_label(self.spec.label, unit)
        for fd in self.frames:  # the values drawn, in the colour bar's unit
            arr = vnp.numpy_to_vtk(np.ascontiguousarray(fd.values * self.factor), deep=True,
                                   array_type=vtkDoubleArray().GetDataType())
            arr.SetName(VALUE)
            (fd.grid.GetPointData() if self.spec.where == "point" else fd.grid.GetCellData()).AddArray(arr)
        self.tfmt = r2.time_format(self.all_times)
        W = int(a.width) // 2 * 2
        self.size = (W, int(round(W * 0.625)) // 2 * 2)
        # Mesh edges on small meshes only: on a fine one they would darken the picture.
        self.show_mesh_edges = first.GetNumberOfCells() <= 3000

    def draw_range(self, lo: int, hi: int) -> list[Path]:
        views = [View(self, section=False), View(self, section=True)]
        written = []
        for fd in self.frames[lo:hi]:
            for v in views:
                written.append(v.draw(fd))
        for v in views:
            v.close()
        return written

    def run(self) -> list[Path]:
        self.load()
        n = len(self.frames)
        jobs = max(1, min(self.a.jobs or (os.cpu_count() or 1), 8, n // 4 or 1))
        written: list[Path] = []
        with offscreen_display():
            if jobs > 1:
                # Frames are independent: fork workers that each build their windows once and draw
                # a contiguous share (the frames are inherited, nothing is pickled but paths). The
                # parent opens no window, so no GL context crosses the fork.
                import multiprocessing as mp

                global _RENDERER
                _RENDERER = self
                chunk = max(1, min(10, math.ceil(n / (jobs * 3))))
                ranges = [(i, min(n, i + chunk)) for i in range(0, n, chunk)]
                done = 0
                with mp.get_context("fork").Pool(jobs) as pool:
                    for paths in pool.imap(_draw_range, ranges):
                        written += paths
                        done += len(paths) // 2
                        if not self.a.quiet and n > 5:
                            print(f"  rendered {done}/{n} frames", flush=True)
            else:
                views = [View(self, section=False), View(self, section=True)]
                for i, fd in enumerate(self.frames):
                    for v in views:
                        written.append(v.draw(fd))
                    if not self.a.quiet and n > 5 and ((i + 1) % max(1, n // 10) == 0 or i + 1 == n):
                        print(f"  rendered {i + 1}/{n} frames", flush=True)
                for v in views:
                    v.close()
        outputs = list(written)
        if self.a.movie:
            surface = [p for p in written if "_section_" not in p.name]
            section = [p for p in written if "_section_" in p.name]
            outputs.append(self.r2.make_movie(surface, self.render_dir / f"{self.safe_key}.mp4", self.a.fps))
            outputs.append(self.r2.make_movie(section, self.render_dir / f"{self.safe_key}_section.mp4", self.a.fps))
        return outputs


_RENDERER: Renderer3D | None = None


def _draw_range(r: tuple[int, int]) -> list[Path]:
    return _RENDERER.draw_range(*r)


def render(args, out: Path, r2) -> list[Path]:
    """The 3D rendering of render_fields.main (r2: that module, for the shared frame selection,
    option parsing, colours and movie)."""
    try:
        return Renderer3D(args, out, r2).run()
    except RenderUnavailable as e:
        lib.fail(str(e), 1)
        raise  # not reached
