"""`lagcli report SPEC -o page.html`: one self-contained page per spec, rendered by a real
browser (issue 21, "a page to share").

Headless Chromium (Debian's `chromium`; skipped with the reason when missing) loads each
page from a file with networking disabled. A probe script, added to a COPY of the page
(the page itself needs no JavaScript), writes what the browser laid out into the title,
which `--dump-dom` prints: the page is no wider than the window (nothing overflows), the
equations are MathML elements laid out as mathematics (a fraction is taller than a line
of text), and no raw LaTeX is left in the text. The whole pages (with plot and
animation) are also screenshotted.
"""
from __future__ import annotations

import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import lagcli
from conftest import SPECS

CHROMIUM = next((shutil.which(n) for n in ("chromium", "chromium-browser", "google-chrome")
                 if shutil.which(n)), None)
needs_chromium = pytest.mark.skipif(CHROMIUM is None, reason="no chromium: pages are not rendered")
BUNDLED = sorted(p.relative_to(SPECS).with_suffix("").as_posix()          # events: hybrid/
                 for p in [*SPECS.glob("*.yaml"), *SPECS.glob("hybrid/*.yaml")])
WIDTH = 1000
PROBE = """<script>
const m = document.querySelectorAll('math'), f = document.querySelector('mfrac, mtable');
document.title = ['probe', document.documentElement.scrollWidth, window.innerWidth, m.length,
  f ? f.getBoundingClientRect().height : 0, document.body.innerText.length].join(':');
</script></body>"""


def browse(html: str, folder: Path, name: str, screenshot: bool = False) -> dict:
    probe = folder / f"{name}.probe.html"
    probe.write_text(html.replace("</body>", PROBE), encoding="utf-8")
    flags = [CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run",
             f"--window-size={WIDTH},900", "--proxy-server=127.0.0.1:9", "--proxy-bypass-list=<-loopback>"]
    dom = subprocess.run([*flags, "--dump-dom", probe.as_uri()], capture_output=True, text=True,
                         timeout=120).stdout
    shot = folder / f"{name}.png" if screenshot else None
    if shot:
        subprocess.run([*flags, f"--screenshot={shot}", probe.as_uri()], capture_output=True, timeout=120)
    title = re.search(r"<title>probe:([^<]*)</title>", dom)
    assert title, f"{name}: the browser did not run the probe\n{dom[:500]}"
    scroll, inner, maths, frac, text = (float(x) for x in title.group(1).split(":"))
    return {"scroll": scroll, "inner": inner, "maths": maths, "frac": frac, "text": text, "dom": dom,
            "shot": shot}


def assert_rendered(seen: dict, name: str):
    assert seen["scroll"] <= seen["inner"], f"{name}: the page is {seen['scroll']} px wide in a {seen['inner']} px window"
    assert seen["maths"] >= 3, f"{name}: {seen['maths']} MathML elements"
    assert seen["frac"] > 20, f"{name}: MathML not laid out as mathematics"
    visible = re.sub(r"<[^>]+>", " ", seen["dom"].split("<body>", 1)[-1].split("<pre>")[0])
    assert not re.search(r"\\(frac|begin|left|mathrm)|\$\$", visible), f"{name}: raw LaTeX in the page"
    assert seen["shot"] is None or (seen["shot"].exists() and seen["shot"].stat().st_size > 1000)


@pytest.mark.core_specs
@needs_chromium
@pytest.mark.parametrize("name", BUNDLED)
def test_every_bundled_page_renders_in_a_browser(tmp_path, name):
    """The equations part of every bundled spec's page (pictures are slow: the next test)."""
    system = lagcli.load(SPECS / f"{name}.yaml")
    assert_rendered(browse(system.page(pictures=False), tmp_path, name.replace("/", "_")), name)


@needs_chromium
@pytest.mark.parametrize("name", ["cart_pole", pytest.param("double_pendulum", marks=pytest.mark.slow),
                                  pytest.param("rolling_disc", marks=pytest.mark.slow)])
def test_whole_page_from_the_command_line(tmp_path, name):
    """`lagcli report SPEC -o page.html`: with the plot (inline SVG) and the animation (GIF)."""
    pytest.importorskip("matplotlib")
    page = tmp_path / "page.html"
    lagcli_command = [sys.executable, "-m", "lagcli"]          # installed or not (PYTHONPATH)
    done = subprocess.run([*lagcli_command, "report", str(SPECS / f"{name}.yaml"), "-o", str(page)],
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    html = page.read_text(encoding="utf-8")
    assert "<svg" in html and "data:image/gif;base64," in html
    again = tmp_path / "again.html"                         # same spec, same bytes
    subprocess.run([*lagcli_command, "report", str(SPECS / f"{name}.yaml"), "-o", str(again)],
                   capture_output=True, timeout=600, check=True)
    assert again.read_bytes() == page.read_bytes()
    assert not re.search(r"""(src|href)=["']https?:""", html), "the page loads something from the network"
    assert_rendered(browse(html, tmp_path, name, screenshot=True), name)


def test_spec_text_is_escaped_in_the_page():
    """A description with markup is shown as text, never as HTML."""
    system = lagcli.load("description: <script>alert(1)</script> & <b>x</b>\ncoordinates: [x]\n"
                         "parameters: {m: 1.0}\nparticles: {P: {mass: m, position: [x, 0]}}\n")
    html = system.page(pictures=False)
    assert "<script>alert" not in html and "&lt;script&gt;alert(1)&lt;/script&gt;" in html
