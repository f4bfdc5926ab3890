"""What each CLI command does, without click: path + options in, text out."""
from __future__ import annotations

import json

from lagcli.api import load_model
from lagcli.derive import derive
from lagcli.emit.report import report_content
from lagcli.emit.spec_printer import spec_str
from lagcli.emit.templates import render


def derive_text(path: str, simplify: bool = True) -> str:
    content = report_content(derive(load_model(path)), spec_str, simplify)
    return render("report/derive.txt.jinja", r=content)


def derive_json(path: str, simplify: bool = True) -> str:
    content = report_content(derive(load_model(path)), spec_str, simplify)
    return json.dumps(content, indent=2) + "\n"


def derive_latex(path: str, simplify: bool = True, standalone: bool = False) -> str:
    from lagcli.emit.latex import latex_document, latex_fragment

    derivation = derive(load_model(path))
    return latex_document(derivation, simplify) if standalone else latex_fragment(derivation, simplify)


def check_summary(path: str) -> str:
    """Validate the spec (through the derivation, which classifies constraints) and summarise."""
    d = derive(load_model(path))
    return render("report/check.txt.jinja", d=d, m=d.model)
