"""How the analyses word their numbers, the modes of a linear model and its verdict: what
the text, JSON, LaTeX and notebook displays of `lagcli.analysis.report` and `results`
share (docs/analysis.md, "Stability verdict")."""
from __future__ import annotations


def number(x: float, digits: int = 10) -> str:
    x = float(x)
    return "0" if x == 0 else f"{x:.{digits}g}"


def complex_text(s: complex, digits: int = 10) -> str:
    if s.imag == 0:
        return number(s.real, digits)
    sign = "-" if s.imag < 0 else "+"
    return f"{number(s.real, digits)} {sign} {number(abs(s.imag), digits)}i"


def pair(s: complex) -> list[float]:
    """A complex number as JSON writes it: [re, im]."""
    return [float(s.real), float(s.imag)]


SETTLED = ("asymptotically stable", "stable", "gyroscopically stabilized", "marginally stable")  # nothing grows


def modes_content(modes) -> list[dict]:
    return [{"eigenvalue": pair(m.eigenvalue), "natural_frequency": m.natural_frequency,
             "damping_ratio": m.damping_ratio, "kind": m.kind} for m in modes]


def drift_sentence(drift) -> str:
    """What the drift of a linear model is, in words (every surface says it so)."""
    verb = "grows" if len(drift) == 1 else "grow"
    return (f"{', '.join(drift)} {verb} linearly with time (s = 0 repeated with fewer eigenvectors: "
            "a neutral mode moving at constant speed); the verdict is on the other modes")


def modes_text(c: dict) -> list[str]:
    lines = ["eigenvalues" + (f" (neutral modes by structure, left out: {', '.join(c['neutral_states'])})"
                              if c["neutral_states"] else "") + ":"]
    lines.append(f"  {'eigenvalue':>34}  {'frequency (rad/s)':>18}  {'damping ratio':>14}  mode")
    for m in c["modes"]:
        zeta = "-" if m["damping_ratio"] is None else number(m["damping_ratio"], 6)
        lines.append(f"  {complex_text(complex(*m['eigenvalue'])):>34}  {number(m['natural_frequency']):>18}"
                     f"  {zeta:>14}  {m['kind']}")
    if c["drift"]:
        lines.append(f"drift: {drift_sentence(c['drift'])}")
    lines.append(f"verdict: {c['verdict']} ({c['evidence']})")
    return lines


def motion_lines(modes: list[dict], verdict: str) -> list[str]:
    """What the modes of an equilibrium do, beyond their eigenvalues: the frequencies of the
    oscillations (small oscillations where nothing grows) and each spiral or defective
    pair in words."""
    lines = []
    frequencies = sorted({round(m["natural_frequency"], 12) for m in modes
                          if m["kind"] == "oscillation" and m["eigenvalue"][1] > 0})
    if frequencies:
        label = "small-oscillation frequencies" if verdict in SETTLED else "frequencies of the modes that oscillate"
        lines.append(f"{label} (rad/s): " + ", ".join(number(w) for w in frequencies))
    for m in modes:
        re, im = m["eigenvalue"]
        if im <= 0 or m["kind"] == "oscillation":
            continue
        if m["kind"].endswith("spiral"):
            change = "grows" if re > 0 else "decays"
            lines.append(f"{m['kind']} {number(re, 8)} +- {number(im, 8)}i: the amplitude {change} as "
                         f"exp({number(re, 8)} t) while turning at {number(im, 8)} rad/s")
        elif m["kind"] == "growing oscillation":
            lines.append(f"growing oscillation +- {number(im, 8)}i: repeated with fewer eigenvectors, the "
                         "amplitude grows like t")
    return lines
