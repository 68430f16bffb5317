"""The lines over the 3-D view: the verdict in two lines, what it says of the file's mesh, thinned layers.

Pure text from the model (no VTK): the view (:mod:`crustview.render.view`) draws them above its legend, in
the window and in rendered files.
"""

from __future__ import annotations

from .describe import verdict_parts


def view_notes(model, in_window: bool = True) -> list[str]:
    """Lines above the legend: M_S is not a closed manifold through every sample; layers drawn thinned.

    ``in_window`` False (a rendered file): no line points at the window's Information panel.
    """
    rec = model.rec
    if rec is None:
        return []
    # layers drawn as a subset say so over the view, too
    thinned = [layer.note for layer in model.layers.values() if layer.visible and layer.note]
    level, words, mesh_notes = verdict_parts(rec, model.truth)
    # what the verdict says of a mesh that cannot judge M_S: a line of its own (one line was cut off)
    about_mesh = [n[0].upper() + n[1:] for n in mesh_notes]
    if level == "ok":
        # the verdict is over the view whatever the dock shows (Steps is in front after a run)
        what = "every part" if rec.d == 1 else "every handle, hole and part"
        return [f"{words} — {what} supported by the sample", *about_mesh] + thinned
    # two lines: the verdict, and its bracket (the uncertain features, or why); a mismatch's Betti tuples stay whole
    if " (uncertain" in words:
        head, rest = words.split(" (uncertain", 1)
        rest = "(uncertain" + rest
    elif words.startswith("M_S is WRONG"):
        head, rest = words, ""
    else:
        head, _, rest = words.partition(" (")
        rest = "(" + rest if rest else ""
    if not in_window:  # a rendered file has no Information panel to point at
        return [head, *([rest] if rest else []), *about_mesh] + thinned
    if not rest and about_mesh:  # the note on the mesh is the why: no line sending the reader elsewhere
        return [head, *about_mesh] + thinned
    return [head, (rest + " — see Information") if rest else "see Information", *about_mesh] + thinned
