"""SceneView: wires a SceneModel to a pyvista plotter through the adapters."""

from __future__ import annotations

import numpy as np
import pyvista as pv

from ..scene.describe import verdict
from ..scene.model import SceneModel
from ..scene.projection import TOUR_SLIDERS as WINDOW_ONLY
from ..scene.subset import even_subset
from ..scene.viewnotes import view_notes
from .base import LayerAdapter
from .compare import CompareAdapter
from .complexes import (
    CandidatesAdapter,
    ManifoldAdapter,
    RemovedAdapter,
    SliceAdapter,
    StepAdapter,
)
from .diagnosis import CascadeAdapter, HolesAdapter, OrientationAdapter, UncertainAdapter
from .frames import FrameGate
from .inspect import SelectionAdapter, VoronoiAdapter
from .legend_entries import COLORED_SWATCH, THEOREMS_FIRST, legend_entries  # noqa: F401 - also imported from here
from .lod import LevelOfDetail
from .navigation import CameraControl
from .overlay import NOTE_COLOR, OK_COLOR, WARN_COLOR, Legend
from .samples import NormalsAdapter, PointsAdapter, PolesAdapter, TruthAdapter
from .shelf import unshelve

#: Adapter of each layer (by layer name), in drawing order.
ADAPTERS: dict[str, type[LayerAdapter]] = {
    "truth": TruthAdapter,
    "candidates": CandidatesAdapter,
    "removed": RemovedAdapter,
    "manifold": ManifoldAdapter,
    "compare": CompareAdapter,
    "slice": SliceAdapter,
    "voronoi": VoronoiAdapter,
    "normals": NormalsAdapter,
    "poles": PolesAdapter,
    "points": PointsAdapter,
    "holes": HolesAdapter,
    "cascade": CascadeAdapter,
    "step": StepAdapter,
    "uncertain": UncertainAdapter,
    "orientation": OrientationAdapter,
    "selection": SelectionAdapter,
}

BACKGROUND = ("#ffffff", "#dde3ea")  # bottom, top
#: Characters above which a scalar bar's title puts its parenthesis on a second line (the bar is 0.38 of the view
#: wide: at 640 px about 240 px, some 30 characters of its 14-point title).
BAR_TITLE_LINE = 30
#: Most raw points the preview draws (an even subset of a bigger file).
PREVIEW_POINTS = 250_000


class SceneView(CameraControl):
    """Draws a :class:`SceneModel` into a pyvista plotter and keeps it current.

    Parameters
    ----------
    model : SceneModel
    plotter : pyvista.Plotter or pyvistaqt.QtInteractor
    """

    def __init__(self, model: SceneModel, plotter) -> None:
        self.model = model
        self.plotter = plotter
        #: The plotter's renders go through it: :meth:`held` batches draw one frame (see :mod:`.frames`).
        self.frames = FrameGate(plotter)
        self.held = self.frames.held
        self.auto_render = True
        #: The plane cutting away what lies in front of a framed step (None: no cut).
        self.clip_plane = None
        #: View the data with its Y axis up instead of Z (View ▸ Y axis up).
        self.y_up = False
        #: Drawn in the window (its notes may point at its docks and sliders); False for rendered files.
        self.in_window = True
        plotter.set_background(BACKGROUND[0], top=BACKGROUND[1])
        # one headlight instead of pyvista's five-light kit: software GL (the usual case here)
        # shades every pixel once per light, and a frame of a large M_S is fill-bound
        plotter.remove_all_lights()
        plotter.add_light(pv.Light(light_type="headlight"))
        self.adapters: dict[str, LayerAdapter] = {}
        for name, cls in ADAPTERS.items():
            layer = model.layers[name]
            a = cls(model, layer, plotter)
            self.adapters[name] = a
            layer.events.visible.connect(lambda *_, a=a: self._on_visible(a))
            for field in ("color", "opacity", "size"):
                getattr(layer.events, field).connect(lambda *_, a=a: self._on_style(a))
            layer.events.colorby.connect(lambda *_: self._after_colour())
            layer.events.mode.connect(lambda *_: (self.update_legend(), self.render()))
            layer.events.shrink.connect(lambda *_: self.render())
        self._on_top(("truth", "compare", "cascade", "step", "uncertain", "orientation", "selection"))
        self._bars: dict[str, object] = {}
        self._stale: set[LayerAdapter] = set()
        self.hud = self._hud()
        self.legend = Legend(plotter, renderer=self.hud)
        # the notes wrap to the view's width: again before a frame whenever that width changed
        plotter.ren_win.AddObserver("StartEvent", lambda *_: self.legend.refit())
        self._to_hud(self.adapters["holes"].label_actor)  # the holes' sizes over the geometry
        self._built_for: int | None = None
        #: Whether the camera was last framed on a stereographic view.
        self._stereo_framed = False
        self.basis_text = plotter.add_text("", position="lower_left", font_size=11, color="#222222", name="basis")
        self._to_hud(self.basis_text)
        tp = self.basis_text.GetTextProperty()
        tp.SetBackgroundColor(1.0, 1.0, 1.0)  # readable over the data too
        tp.SetBackgroundOpacity(0.75)
        self.axes = plotter.add_axes(xlabel="X", ylabel="Y", zlabel="Z", line_width=2)
        model.reconstruction_changed.connect(self.on_reconstruction)
        model.projection.changed.connect(self.on_projection)
        model.player.step_changed.connect(self.on_step)
        model.selection.changed.connect(self.on_selection)
        model.candidates_changed.connect(lambda *_: self._after_colour())
        model.theorems_changed.connect(lambda *_: (self.adapters["points"].recolor(), self._after_colour()))
        model.cascade_changed.connect(lambda *_: (self.update_legend(), self.render()))
        model.slice_changed.connect(lambda *_: (self.update_legend(), self.render()))
        # a new comparison is named in the legend and drawn at once (it waited for the next step)
        model.comparison_changed.connect(lambda *_: (self.update_legend(), self.render()))
        #: Big parts thinned while the view moves or steps (see :mod:`crustview.render.lod`).
        self.lod = LevelOfDetail(plotter.renderer)
        self._watch_interaction()

    def _on_top(self, names: tuple[str, ...]) -> None:
        """Draw these layers in a second renderer layer over the scene.

        The step's removed simplices usually lie *inside* M_S (that is why
        they are removed); drawn in place they would be hidden by the opaque
        surface.  The overlay renderer shares the camera and clears only the
        depth buffer, so the highlight is always seen, in its true place.
        """
        from vtkmodules.vtkRenderingCore import vtkRenderer

        window = self.plotter.render_window
        top = vtkRenderer()
        top.SetLayer(1)
        top.InteractiveOff()
        top.SetActiveCamera(self.plotter.renderer.GetActiveCamera())
        # the same lights as the scene (a layer renderer of its own would light
        # its actors from nowhere and draw them almost black)
        top.AutomaticLightCreationOff()
        top.SetLightCollection(self.plotter.renderer.GetLights())
        window.SetNumberOfLayers(2)
        window.AddRenderer(top)
        for name in names:
            for part in self.adapters[name].parts:
                self.plotter.remove_actor(part.actor, render=False)
                top.AddActor(part.actor)
        self.top_renderer = top
        self.adapters["truth"].overlay = top  # a mesh's faces move into the scene (TruthAdapter._in_scene)

    def _hud(self):
        """A third renderer layer, over the overlay: text, legends and colour bars.

        Geometry never covers them: the step highlight, the cascade and the
        truth (layer 1) used to be drawn over the legend and the bars, which
        were in the scene's layer 0.
        """
        from vtkmodules.vtkRenderingCore import vtkRenderer

        window = self.plotter.render_window
        hud = vtkRenderer()
        hud.SetLayer(2)
        hud.InteractiveOff()
        hud.SetActiveCamera(self.plotter.renderer.GetActiveCamera())
        window.SetNumberOfLayers(3)
        window.AddRenderer(hud)
        return hud

    def _to_hud(self, actor) -> None:
        """Move a 2-D actor pyvista added to the scene's renderer into :attr:`hud`."""
        self.plotter.renderer.RemoveViewProp(actor)
        self.hud.AddViewProp(actor)

    # -- level of detail -----------------------------------------------------
    def _watch_interaction(self) -> None:
        """Thin big layers while the mouse drags the view; draw them whole on release."""
        iren = getattr(self.plotter, "iren", None)
        style = iren.interactor.GetInteractorStyle() if iren is not None else None
        if style is None:
            return
        style.AddObserver("StartInteractionEvent", lambda *_: self.begin_lod())
        style.AddObserver("EndInteractionEvent", lambda *_: self.end_lod())

    def _shown_parts(self) -> list:
        return [p for a in self.adapters.values() if a.layer.visible for p in a.parts]

    def begin_lod(self) -> bool:
        """Draw parts above :data:`~crustview.render.lod.LOD_CELLS` cells thinned until :meth:`end_lod`."""
        return self.lod.begin(self._shown_parts()) if self.ready else False

    def end_lod(self) -> None:
        """Draw every part whole again (one render, if anything was thinned)."""
        if self.lod.end():
            self.render()

    # -- helpers -------------------------------------------------------------
    @property
    def ready(self) -> bool:
        """True once the adapters hold the model's current reconstruction."""
        return self.model.rec is not None and self._built_for == id(self.model.rec)

    def render(self) -> None:
        """A frame of the current picture, through :attr:`frames` (see :mod:`.frames`).

        Owed inside a batch, a paint asked for in the window (many changes before the next paint cost one
        frame), else drawn at once.
        """
        if self.auto_render:
            self.plotter.render()

    def _on_visible(self, a: LayerAdapter) -> None:
        self.lod.end()  # a thinned copy must not outlive its layer's visibility
        if a.layer.visible and a in self._stale and self.ready:
            # hidden layers skip updates; catch up once when shown again
            self._stale.discard(a)
            a.rebuild()
            a.restyle()
            a.layer.stale = False
        a.apply_visibility()
        self.update_overlays()
        self.render()

    def _on_style(self, a: LayerAdapter) -> None:
        if self.ready:
            a.restyle()
        self.update_legend()
        self.render()

    def _after_colour(self) -> None:
        self.update_overlays()
        self.render()

    def _live(self):
        """Adapters of visible layers; the hidden ones are marked stale."""
        for a in self.adapters.values():
            if a.layer.visible:
                yield a
            else:
                self._stale.add(a)

    # -- model events ------------------------------------------------------------
    def show_preview(self, points: np.ndarray | None) -> None:
        """Draw raw input points (first three coordinates, centred) before any result exists.

        Used while the dimension is asked and the first reconstruction runs,
        so the window is never empty; ``None`` removes the preview.  One frame (see :mod:`.frames`).
        """
        with self.held():
            self._preview(points)

    def _preview(self, points: np.ndarray | None) -> None:
        if points is None:
            if self.plotter.actors.get("preview") is not None:
                self.plotter.remove_actor("preview", render=False)
                self.render()
            return
        p = np.asarray(points, dtype=float)
        n = len(p)
        # a million raw points cost a second per frame in software GL: an even subset stands in
        keep = even_subset(n, PREVIEW_POINTS)
        points_layer = self.model.layers["points"]
        points_layer.count = len(keep)  # the layer panel counts what is drawn
        points_layer.total = n if len(keep) < n else 0
        points_layer.note = (
            f"Raw points: drawn {len(keep):,} of {n:,} while the reconstruction runs" if len(keep) < n else ""
        )
        p = p[keep] - p.mean(axis=0)
        flat = p.shape[1] == 2
        p3 = np.zeros((len(p), 3))
        p3[:, : min(3, p.shape[1])] = p[:, :3]
        import pyvista as pv

        self.plotter.add_mesh(
            pv.PolyData(p3),
            name="preview",
            color="#34495e",
            point_size=3.0,
            render_points_as_spheres=False,
            pickable=False,
            reset_camera=False,
            render=False,
        )
        if flat:
            self.plotter.view_xy(render=False)
        else:
            self.aim()  # from where the result will be seen
        self.plotter.reset_camera(
            render=False, bounds=tuple(np.ravel(np.stack([p3.min(axis=0), p3.max(axis=0)], axis=1)))
        )
        self.render()

    def on_reconstruction(self) -> None:
        with self.held():  # one frame for the layers, the overlays and the camera
            self._on_reconstruction()

    def _on_reconstruction(self) -> None:
        rec = self.model.rec
        if rec is None:
            return
        unshelve(self)  # the previous result's props, set aside while this one's points were previewed
        self.show_preview(None)
        self.clear_clip()
        self.lod.end()
        self._built_for = id(rec)
        self._stereo_framed = self.model.projection.stereographic
        self._stale.clear()
        for a in self.adapters.values():
            a.rebuild()
            a.restyle()
            a.apply_visibility()
            a.layer.stale = False
        self.update_overlays()
        self.update_basis_text()
        if not self.model.kept_view:
            self.reset_camera()
        self.render()

    def on_projection(self) -> None:
        if not self.ready:
            return
        self.clear_clip()  # the cut was placed for the old projection
        for a in self._live():
            a.project()
        if self.model.projection.stereographic != self._stereo_framed:
            # to or from the stereographic view: new geometry, framed (the camera sat inside it)
            self._stereo_framed = self.model.projection.stereographic
            self.reset_camera()
        if self.lod.active:
            self.lod.begin(self._shown_parts())  # the grand tour moves the points of thinned parts
        self.update_basis_text()
        self.update_bars()  # a colouring by the hidden depth names the direction, which turned
        self.render()

    def on_step(self, *_) -> None:
        if not self.ready:
            return
        for a in self._live():
            if a.uses_step:
                a.step()
        for a in self._stale:
            if a.uses_step and not a.layer.stale:
                a.layer.stale = True  # its count is of an earlier step: the panel says so
        if self.lod.active:
            self.lod.begin(self._shown_parts())  # re-thin what the step changed
        self.update_legend()
        self.render()

    def on_selection(self) -> None:
        if not self.ready:
            return
        for a in self._live():
            if a.uses_selection:
                a.select()
        self.update_legend()  # the poles and the Voronoi cell appear with a selected sample
        self.render()

    # -- overlays ------------------------------------------------------------
    def update_overlays(self) -> None:
        self.update_bars()
        self.update_legend()

    def update_bars(self) -> None:
        """One scalar bar per visible scalar colouring (points, candidates)."""
        want = {}
        for name in ("points", "manifold", "candidates", "removed"):
            a = self.adapters[name]
            title = getattr(a, "scalar_title", None)
            if self.model.layers[name].visible and title:
                # the lookup table too: a new file's epsilon bounds come in a new table, and a
                # bar kept for the same title and mapper showed the last file's range and marks
                want[title] = (a.part.mapper, a.part.mapper.GetLookupTable())
        if list(self._bars.items()) != list(want.items()):
            # the bars stack in order: one that stays keeps its place only if all before it stay
            for title in list(self._bars):
                self.hud.RemoveViewProp(self.plotter.scalar_bars[title])
                self.plotter.remove_scalar_bar(title, render=False)
            self._bars = {}
        for j, (title, (mapper, lut)) in enumerate(want.items()):
            if title not in self._bars:
                # horizontal, bottom right, below the data: the title fits and stays readable
                bar = self.plotter.add_scalar_bar(
                    title=title,
                    mapper=mapper,
                    vertical=False,
                    position_x=0.58,
                    position_y=0.05 + 0.13 * j,
                    height=0.07,
                    width=0.38,
                    n_labels=5,
                    fmt="%.3g",
                    color="#222222",
                    title_font_size=14,
                    label_font_size=12,
                    bold=False,
                )
                if len(title) > BAR_TITLE_LINE and " (" in title:
                    # a long title (the hidden depth's direction) on two lines: at 640 x 480 it ran off the view
                    head, _, tail = title.partition(" (")
                    bar.SetTitle(f"{head}\n({tail}")
                bar.GetTitleTextProperty().SetBackgroundColor(1.0, 1.0, 1.0)
                bar.GetTitleTextProperty().SetBackgroundOpacity(0.75)
                self._to_hud(bar)
                self._bars[title] = (mapper, lut)

    def legend_entries(self) -> list[tuple[str, str]]:
        """(label, colour) of the visible solid-colour layers and the step highlight (:mod:`.legend_entries`)."""
        return legend_entries(self)

    def update_legend(self) -> None:
        level = verdict(self.model.rec, self.model.truth)[0] if self.model.rec is not None else "ok"
        color = {"ok": OK_COLOR, "warn": WARN_COLOR}.get(level, NOTE_COLOR)
        self.legend.set(self.legend_entries(), self.notes(), color)

    def notes(self) -> list[str]:
        """Lines above the legend (:func:`~crustview.scene.viewnotes.view_notes`)."""
        return view_notes(self.model, self.in_window)

    def update_basis_text(self) -> None:
        p = self.model.projection
        if p.flat:
            text = "2-D data shown flat: X = x1, Y = x2"
        else:
            lab = p.axis_labels()
            where = p.description if self.in_window else p.description.replace(WINDOW_ONLY, "")
            text = f"view axes: {where}\nX = {lab[0]}    Y = {lab[1]}    Z = {lab[2]}"
            if p.stereographic:  # the axes are the numerators only: say what the drawn coordinates are
                text = (
                    f"view axes: stereographic, each axis times r / (r - h), h along the hidden direction, "
                    f"r = {p.stereo_radius:.3g} ({where})\nX = {lab[0]}    Y = {lab[1]}    Z = {lab[2]}"
                )
        self.basis_text.SetText(0, text)
