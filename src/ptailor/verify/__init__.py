"""Re-drape check: sew a pattern on a body with a real cloth solver and measure the fit.

Modules (imported on demand; nothing here pulls in the cloth engine):

- :mod:`ptailor.verify.engine`: :func:`~ptailor.verify.engine.redrape` on NVIDIA Newton's
  Style3D cloth solver (optional: ``pip install 'ptailor[sim]'``; newton and warp are imported
  only inside its functions).
- :mod:`ptailor.verify.rest`: each triangle's rest shape from a pattern.
- :mod:`ptailor.verify.measure`: principal stretches, per-panel statistics, the top opening.
- :mod:`ptailor.verify.settle`: when a re-drape has settled (speed, displacement over a
  window), and why not.
- :mod:`ptailor.verify.check`: the three re-drapes (ours and baseline from the edited drape,
  the original from the original drape: the null test), the report section.
- :mod:`ptailor.verify.verdict`: the null test and the verdict, from a section alone.
- :mod:`ptailor.verify.summary`: the check in a few terminal lines.
- :mod:`ptailor.verify.picture`: ``verify.png``.
"""
