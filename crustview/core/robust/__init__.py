"""The robust extension: what runs where the paper's Algorithm 3 cannot close M_S.

:mod:`.driver` (``extract_robust``) runs the paper's loop first and keeps
its result whenever it is a closed manifold through every sample; otherwise
it runs the extension's rules, each named as in the step log:

* ``seed-core``: :mod:`.seed_core`, the part of T_S that the walk would take
  without a choice.
* ``seed``, ``grow``, ``grow-relaxed``: :mod:`.grow` (one growing front,
  its three phases), with :mod:`.handles` refusing gap handles.
* ``fill-hole``: :mod:`.fill_hole` (with :mod:`.polygons` for ears).
* ``drop-stray``: :mod:`.drop_stray`.
* ``insert-sample``: :mod:`.insert_sample`.

May import: everything in :mod:`crustview.core` except
:mod:`~crustview.core.reconstruct` (which imports this package); never the
viewer (scene, render, qt).
"""
