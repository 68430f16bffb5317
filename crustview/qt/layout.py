"""The window's dock layout: the 3-D view keeps at least 60 % of the width."""

from __future__ import annotations

from PySide6.QtCore import Qt, QTimer
from PySide6.QtWidgets import QTabBar

#: Share of the window's width the 3-D view keeps; below it the docks collapse to tabs.
VIEW_SHARE = 0.6
#: From this window width on, the Information dock stands beside the tabbed column, not in it.
WIDE = 1800


class DockLayout:
    """Mixin of :class:`~crustview.qt.window.MainWindow`: the docks in one tabbed column when space is short.

    The docks collapse to one tabbed column whenever the view would get less
    than :data:`VIEW_SHARE` of the window.  Needs ``plotter``, ``docks``,
    ``layers_panel``, ``steps_panel`` and ``compact``.
    """

    def fit_to_screen(self, width: int, height: int) -> None:
        """Size the window for a screen of ``width`` x ``height`` pixels.

        The docks then collapse to one tabbed column if the 3-D view would
        otherwise get less than :data:`VIEW_SHARE` of the window (as on any
        later resize).
        """
        w, h = min(1600, int(width * 0.95)), min(1000, int(height * 0.92))
        if width < 1400:  # surely too narrow for docks side by side: collapse before sizing
            self.resize(w, h)
            self.compact_docks()
        self.resize(w, h)
        self.keep_view_share()

    @property
    def view_share(self) -> float:
        """The 3-D view's share of the window's width."""
        return self.plotter.width() / max(1, self.width())

    def resizeEvent(self, event) -> None:  # noqa: N802 - Qt API
        super().resizeEvent(event)
        if self.isVisible():
            QTimer.singleShot(0, self.keep_view_share)

    def setVisible(self, visible: bool) -> None:  # noqa: N802 - Qt API
        if visible and not self.isVisible():
            # before the first paint: a window that opens too narrow for its docks side by side opens with
            # them tabbed, not rearranged in front of the user after its first frame (and drawn again)
            self._fit_docks()
        super().setVisible(visible)

    def showEvent(self, event) -> None:  # noqa: N802 - Qt API
        super().showEvent(event)
        QTimer.singleShot(0, self.keep_view_share)

    def keep_view_share(self) -> None:
        """Collapse the docks to one tabbed column when the view would drop below :data:`VIEW_SHARE`.

        Once collapsed, the column is sized again at every resize so the view keeps its share.
        """
        if self.isVisible():
            self._fit_docks()

    def _fit_docks(self) -> None:
        """:meth:`keep_view_share` at the window's present size, shown or not.

        The layout gives a hidden window the same widths as a shown one (measured from 1,024 to 3,000 px).
        """
        self.layout().activate()  # the docks' real widths at this window size
        if self.compact:
            if self._set_wide(self.width() >= WIDE) or self.view_share < VIEW_SHARE - 0.02:
                self._size_column()
            return
        if self.view_share < VIEW_SHARE:
            self.compact_docks()

    def compact_docks(self) -> None:
        """All docks in one tabbed column on the right (Steps in front), narrow enough for the view."""
        if self.compact:
            return
        self.compact = True
        self.layers_panel.compact()  # narrower widgets: no scrolling sideways at 1024 px
        self.steps_panel.compact()
        self.docks["steps"].setWindowTitle("Steps")
        right = Qt.DockWidgetArea.RightDockWidgetArea
        order = ["steps", "run", "layers", "projection", "info"]
        for name in order:
            self.addDockWidget(right, self.docks[name])
        for name in order[1:]:
            self.tabifyDockWidget(self.docks["steps"], self.docks[name])
        self.docks["steps"].raise_()
        self._set_wide(self.width() >= WIDE)
        self._size_column()
        QTimer.singleShot(0, self._size_column)  # again once the tabbed layout has settled
        for bar in self.findChildren(QTabBar):  # whole titles, scrolled when they do not fit
            bar.setElideMode(Qt.TextElideMode.ElideNone)
            bar.setUsesScrollButtons(True)
            bar.setExpanding(False)

    def _set_wide(self, wide: bool) -> bool:
        """Information beside the tabbed column (a wide window uses its width) or back among its tabs.

        Returns whether the layout changed.
        """
        if not self.compact or wide == getattr(self, "wide", False):
            return False
        self.wide = wide
        steps, info = self.docks["steps"], self.docks["info"]
        if wide:
            self.removeDockWidget(info)  # out of the tab group, then beside it in the same area
            self.addDockWidget(Qt.DockWidgetArea.RightDockWidgetArea, info, Qt.Orientation.Horizontal)
        else:
            self.tabifyDockWidget(steps, info)
        info.show()
        steps.raise_()
        return True

    def _size_column(self) -> None:
        column = int(self.width() * (1.0 - VIEW_SHARE) - 12)
        if getattr(self, "wide", False):  # two columns side by side share the docks' width
            steps = max(240, int(column * 0.45))  # the Information panel's tables want the wider half
            self.resizeDocks(
                [self.docks["steps"], self.docks["info"]], [steps, max(240, column - steps)], Qt.Orientation.Horizontal
            )
            return
        self.resizeDocks([self.docks["steps"]], [max(240, column)], Qt.Orientation.Horizontal)
