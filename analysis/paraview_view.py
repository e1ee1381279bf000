#!/usr/bin/pvbatch
# SPDX-License-Identifier: BSD-3-Clause
"""A picture of a run's particles in ParaView, headless: opens RUN.xmf with ParaView's default
reader (Xdmf3ReaderS, as File → Open does), shows frame at time T as points coloured by a field
and writes a PNG. Runs under pvbatch (python3-paraview); without a display, under xvfb-run:

    xvfb-run -a pvbatch analysis/paraview_view.py two_disks.xmf --time 2.4 \\
        --field stress --component 0 --label "stress xx" \\
        -o docs/paraview_two_disks

-o PREFIX writes PREFIX.png (default: the .xmf's name without .xmf), as every script of
analysis/ takes it; a trailing .png is dropped (-o docs/paraview_two_disks.png is the same).
"""

import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from figures import output_prefix  # noqa: E402

from paraview.simple import (ColorBy, GetActiveViewOrCreate, GetColorTransferFunction,
                             GetScalarBar, OpenDataFile, ResetCamera, SaveScreenshot, Show)

ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
ap.add_argument("xmf", help="a run's particle sidecar, e.g. two_disks.xmf")
ap.add_argument("--time", type=float, default=0.0, help="the frame's time (default 0)")
ap.add_argument("--field", default="velocity", help="the array to colour by (default velocity)")
ap.add_argument("--component", type=int, default=-1,
                help="its component (default: the magnitude; stress and F are row-major)")
ap.add_argument("--label", default="", help="the colour bar's title (default: the field's)")
ap.add_argument("-o", "--output", "--out", dest="out", default="", metavar="PREFIX",
                help="output prefix: writes PREFIX.png; a trailing .png is dropped "
                     "(default: the .xmf's name without .xmf)")
args = ap.parse_args()

reader = OpenDataFile(os.path.abspath(args.xmf))  # Xdmf3 needs a directory in the name
view = GetActiveViewOrCreate("RenderView")
view.ViewSize = [800, 600]
view.ViewTime = args.time
view.OrientationAxesVisibility = 1
shown = Show(reader, view)
shown.SetRepresentationType("Points")
shown.PointSize = 4
if args.component < 0:
    ColorBy(shown, ("POINTS", args.field, "Magnitude"))
else:
    ColorBy(shown, ("POINTS", args.field, str(args.component)))
shown.RescaleTransferFunctionToDataRange(True, False)
shown.SetScalarBarVisibility(view, True)
bar = GetScalarBar(GetColorTransferFunction(args.field), view)
bar.Title = args.label or args.field
bar.ComponentTitle = "" if args.label else ("|.|" if args.component < 0 else f"[{args.component}]")
view.CameraPosition = [0, 0, 1]
view.CameraFocalPoint = [0, 0, 0]
view.CameraViewUp = [0, 1, 0]
ResetCamera(view)
out = output_prefix(args.out or os.path.splitext(args.xmf)[0]) + ".png"
SaveScreenshot(out, view, ImageResolution=[800, 600])
print(f"wrote {out} (t = {args.time}, {args.field})")
