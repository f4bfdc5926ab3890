"""Reports of a derivation for people: text, JSON, LaTeX and the notebook parts.

    content.py         report_content / check_content: the values every report format shows
    latex.py           the LaTeX fragment and document (latex_printer.py: names, `latex:` keys)
    display.py         display forms of equations; naming.py: named subexpressions of big systems
    parts.py           system.parts: each piece as a notebook object
"""
