"""The camera of a :class:`~crustview.render.view.SceneView`: resetting, framing, clipping and picking."""

from __future__ import annotations

import numpy as np

from ..core.steps import PLACELESS_RULES
from ..scene import geometry as geo
from .fitting import fit_clear, text_block
from .framing import frame_for, front_plane, place_camera
from .picking import pick_visible

#: Median spacings shown at least on each side of a feature that a click frames: about the smallest loop
#: the features analysis calls sure (LOOP_SUPPORTED = 4 pi radii), so the parts around a small feature
#: are in the view with it.
FEATURE_CONTEXT = 12.0


class CameraControl:
    """Mixin of :class:`~crustview.render.view.SceneView` (needs ``model``, ``plotter``, ``adapters``, ``y_up``)."""

    # -- camera and picking ---------------------------------------------------
    def reset_camera(self) -> None:
        """Fit the camera to a sphere around the data (stable under rotations); no clipping."""
        self.clear_clip()
        if self.model.rec is None:
            return
        self.plotter.renderer.GetActiveCamera().SetWindowCenter(0.0, 0.0)
        r = self.model.radius
        flat = self.model.projection.flat
        if flat:
            self.plotter.view_xy(render=False)
            self.plotter.enable_parallel_projection()
            bounds = (-r, r, -r, r, 0.0, 0.0)
        else:
            self.plotter.disable_parallel_projection()
            self.aim(r)
            p = self.model.projection.project(self.model.rec.points)
            lo, hi = p.min(axis=0), p.max(axis=0)
            bounds = tuple(np.ravel(np.stack([lo, hi], axis=1)))
        # the bounding sphere of the projected data fills the view: nothing clipped, whatever the
        # aspect of the window (no extra zoom, which cut off the top of tall parts)
        self.plotter.reset_camera(bounds=bounds)
        if not flat:
            # then the data's image moves clear of the legend, the caption and the colour bars (the legend laid out
            # for the view's width now: inside a batch of edits no frame has done it yet, see render.frames)
            if hasattr(self, "legend"):
                self.legend.refit()
            fit_clear(self.plotter.renderer, p, self.text_blocks())

    def text_blocks(self) -> list:
        """Display rectangles of the text over the view: legend and notes, caption, colour bars."""
        ren = self.plotter.renderer
        w, h = ren.GetSize()
        blocks = []
        legend = text_block(self.legend.actors, ren) if hasattr(self, "legend") else None
        if legend is not None:
            blocks.append(legend)
        caption = getattr(self, "basis_text", None)
        if caption is not None and caption.GetText(0):
            # a corner annotation scales its font with the window: about 0.055 of the height a line pair
            lines = caption.GetText(0).count("\n") + 1
            width = max(len(t) for t in caption.GetText(0).split("\n"))
            blocks.append((0.0, 0.0, min(w, 9.0 * width + 10), lines * (0.028 * h + 6)))
        for bar in self.plotter.scalar_bars.values():
            if not bar.GetVisibility():
                continue
            x, y = bar.GetPositionCoordinate().GetValue()[:2]
            blocks.append((x * w, y * h, (x + bar.GetWidth()) * w, (y + bar.GetHeight()) * h + 24))
        return blocks

    def aim(self, r: float = 1.0) -> None:
        """The reset's view direction, from ``r`` away: also the raw points' preview, so the view does not turn."""
        cam = self.plotter.camera
        cam.SetWindowCenter(0.0, 0.0)
        cam.focal_point = (0.0, 0.0, 0.0)
        if self.y_up:  # scans are often stored Y-up (the bunny, spot)
            cam.position = (1.6 * r, 1.4 * r, 2.2 * r)
            cam.up = (0.0, 1.0, 0.0)
        else:
            cam.position = (1.6 * r, -2.2 * r, 1.4 * r)
            cam.up = (0.0, 0.0, 1.0)

    def frame_step(self, step) -> None:
        """Look at ``step``'s tau from its open side and cut away the geometry in front (:mod:`.framing`)."""
        rec = self.model.rec
        if rec is None or step is None:
            return
        if step.rule in PLACELESS_RULES:  # one step everywhere (label-cells): no place to look at
            return
        ext = rec.extraction
        ids = list(step.kept) + list(step.removed) + list(step.added)
        tau = np.asarray(step.tau, dtype=np.int64)
        patch = ext.simplices[ids].ravel() if ids else tau
        if self.model.projection.flat:
            self.frame_points(np.unique(np.concatenate([tau, patch])))
            return
        proj = self.model.projection.project(rec.points)
        cam = self.plotter.renderer.GetActiveCamera()
        frame = frame_for(
            proj,
            tau,
            np.asarray(patch, dtype=np.int64),
            float(np.median(self.model.spacing)),
            proj.mean(axis=0),
            np.asarray(cam.GetViewUp()),
        )
        self.plotter.disable_parallel_projection()
        place_camera(cam, frame)
        self.set_clip(front_plane(frame))
        self.plotter.renderer.ResetCameraClippingRange()
        self.render()

    def set_clip(self, plane) -> None:
        """Clip every scene actor (not the overlay) by ``plane``; None removes the clip."""
        self.clip_plane = plane
        for name, a in self.adapters.items():
            if name in ("step", "cascade", "uncertain", "orientation", "selection"):
                continue
            for part in a.parts:
                part.mapper.RemoveAllClippingPlanes()
                if plane is not None:
                    part.mapper.AddClippingPlane(plane)

    def clear_clip(self) -> None:
        """Show the whole scene again (after framing a step)."""
        if self.clip_plane is not None:
            self.set_clip(None)

    def frame_points(self, idx, around: float = 2.5) -> None:
        """Zoom the camera onto samples ``idx`` (keeps the view direction).

        At least ``around`` median spacings are shown on each side of their centre, and all of them: a set
        wider than that fills the view (a box twice its size put a dispute spanning the whole foot three
        times farther off than the reset view).
        """
        rec = self.model.rec
        if rec is None or len(idx) == 0:
            return
        p = self.model.projection.project(rec.points[np.asarray(idx)])
        lo, hi = p.min(axis=0), p.max(axis=0)
        pad = max(0.5 * float(np.max(hi - lo)), around * float(np.median(self.model.spacing)))
        c = (lo + hi) / 2
        bounds = np.ravel(np.stack([c - pad, c + pad], axis=1))
        self.plotter.renderer.GetActiveCamera().SetWindowCenter(0.0, 0.0)
        self.plotter.reset_camera(bounds=tuple(bounds))
        self.render()

    def frame_simplex(self, vertices) -> None:
        """Look at one simplex (sample indices) along its normal, from its open side.

        What lies in front is cut away (as :meth:`frame_step` does for a step's tau).
        """
        rec = self.model.rec
        if rec is None:
            return
        tau = np.asarray(vertices, dtype=np.int64)
        if self.model.projection.flat or len(tau) < 2:
            self.frame_points(tau)
            return
        proj = self.model.projection.project(rec.points)
        cam = self.plotter.renderer.GetActiveCamera()
        frame = frame_for(
            proj, tau, tau, float(np.median(self.model.spacing)), proj.mean(axis=0), np.asarray(cam.GetViewUp())
        )
        self.plotter.disable_parallel_projection()
        place_camera(cam, frame)
        self.set_clip(front_plane(frame))
        self.plotter.renderer.ResetCameraClippingRange()
        self.render()

    def frame_cascade(self, cascade) -> None:
        """Frame the origin face of a prune cascade with the simplices its first step removed."""
        rec = self.model.rec
        if rec is None or cascade is None:
            return
        first = rec.extraction.steps[cascade.origin]
        ids = np.concatenate(
            [np.asarray(cascade.tau, dtype=np.int64), rec.extraction.simplices[list(first.removed)].ravel()]
        )
        self.frame_points(np.unique(ids))

    def frame_feature(self, feature) -> None:
        """Frame one of ``rec.features`` (a handle's loop, a hole's rim, a component's closest approach)."""
        from ..scene.features import feature_samples

        rec = self.model.rec
        if rec is None or feature is None:
            return
        self.clear_clip()
        self.model.selection.select_feature(feature)  # which one it is: its samples highlighted
        # with what lies around it: a loop of a few samples framed alone fills the view with its own
        # triangles (a bridge between two fingers showed neither finger)
        self.frame_points(feature_samples(rec, feature), around=FEATURE_CONTEXT)

    def frame_face(self, face) -> None:
        """Frame a (d-1)-face with its incident simplices at the current step."""
        rec = self.model.rec
        if rec is None:
            return
        alive = rec.extraction.alive(self.model.player.position)
        simp = rec.extraction.simplices[alive]
        inc = simp[geo.simplices_at_face(simp, face)]
        self.frame_points(np.unique(np.concatenate([np.asarray(face), inc.ravel()])))

    def pick(self, x: float, y: float) -> tuple[str, object] | None:
        """Element under display position ``(x, y)`` (VTK pixels, origin bottom-left).

        The nearest *visible* thing: the current step's own simplices first
        (they are drawn over everything), then M_S and the other simplicial
        layers, then samples, compared by depth (:mod:`.picking`).
        """
        return pick_visible(self, x, y)
