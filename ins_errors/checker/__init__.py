"""The hand-written linearisation checker.

Stages, one module each: :mod:`.parse` (text and LaTeX equations to SymPy, directives),
:mod:`.notation` (the names a hand file may use, from the model definition),
:mod:`.sides` (both sides of an equation in model terms), :mod:`.reference` (reference
motions and Schuler-consistent typical magnitudes), :mod:`.compare` (coefficients at the
reference points, the driver :func:`~.compare.check_hand_file`), :mod:`.classify` (what a
difference is, how much it matters, root or knock-on, declared drop), :mod:`.effect`
(its effect on the 1 h / 24 h error) and :mod:`.report` (Markdown, terminal, JSON). The
matrix check of hand-coded F and G lives beside them (:mod:`.matrix`).
"""
