"""The report in headless Chromium (issue 22): no script error, every plot of plots/ drawn
with a size, and the page's own check catches a broken script and a missing plot.

usage: report_browser_test.py <grapebench> <scene.yaml> <scratch folder> [--no-3d] [screenshot.png]
--no-3d: the protocol's report has no 3D view (classification); it must then be absent.
"""
import re
import shutil
import subprocess
import sys
from pathlib import Path


def browse(page):
    """The DOM after load, as headless Chromium leaves it."""
    out = subprocess.run(["chromium", "--headless", "--no-sandbox", "--disable-gpu", "--virtual-time-budget=20000",
                          "--dump-dom", page.resolve().as_uri()],
                         check=True, capture_output=True, text=True, timeout=180)
    body = re.search(r'<body([^>]*)>', out.stdout)
    attributes = dict(re.findall(r'data-(\w+)="([^"]*)"', body.group(1) if body else ""))
    assert "plots" in attributes, "the page's self-check did not run:\n" + out.stdout[-2000:]
    check = re.search(r'<p id="report-check">([^<]*)', out.stdout)
    return int(attributes["plots"]), int(attributes["errors"]), attributes.get("viewer", ""), check.group(1) if check else ""


def main():
    args = sys.argv[1:]
    no_3d = "--no-3d" in args
    args = [a for a in args if a != "--no-3d"]
    exe, scene, scratch = args[0], args[1], Path(args[2])
    screenshot = args[3] if len(args) > 3 else None
    shutil.rmtree(scratch, ignore_errors=True)
    subprocess.run([exe, "run", scene, "-q", "--out", str(scratch)], check=True, stdout=subprocess.DEVNULL)
    folder = next(p for p in scratch.iterdir() if p.is_dir())
    report = folder / "report.html"
    plot_files = sorted((folder / "plots").glob("*.svg"))
    assert plot_files, "no plots written"
    drawn, errors, viewer, line = browse(report)
    print(f"{report}: {line}; 3D view: {viewer}")
    assert errors == 0, line
    assert drawn >= len(plot_files), f"{drawn} plots drawn, {len(plot_files)} in plots/"
    if no_3d:  # classification: the berry ROC, in full and magnified, must be among them
        assert report.read_text().count("berry ROC") >= 2, "no ROC plots in the classification report"
    if no_3d:
        assert viewer == "", f"a 3D view where the protocol has none: '{viewer}'"
    else:
        assert viewer == "drawn", f"the 3D view of the first bunch was not drawn: '{viewer}'"
    # The check can fail: a broken script and a plot taken out are both seen.
    html = report.read_text()
    broken = folder / "broken.html"
    broken.write_text(html.replace("</body>", "<script>undefinedFunction();</script></body>", 1))
    _, errors_broken, _, _ = browse(broken)
    assert errors_broken == 1, errors_broken
    first_svg = html.index("<svg")
    missing = folder / "missing.html"
    missing.write_text(html[:first_svg] + html[html.index("</svg>", first_svg) + len("</svg>"):])
    drawn_missing, _, _, _ = browse(missing)
    assert drawn_missing == drawn - 1, (drawn_missing, drawn)
    if screenshot:
        subprocess.run(["chromium", "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
                        "--virtual-time-budget=20000", "--window-size=1400,2000", "--screenshot=" + screenshot,
                        report.resolve().as_uri()], check=True, capture_output=True, timeout=180)


if __name__ == "__main__":
    main()
