"""The hand-written linearisation checker.

Stages, one module each: :mod:`.parse` (text and LaTeX equations to SymPy),
:mod:`.notation` (the names a hand file may use), :mod:`.reference` (the model's own
variation at reference motion points), :mod:`.compare` (term-by-term comparison and
classification) and :mod:`.report` (Markdown, text and JSON reports).
"""
