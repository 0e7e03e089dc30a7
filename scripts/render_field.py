"""Render one field of fe_server's snapshots (<out>_fields.xdmf) to a PNG with
ParaView, for a report or a quick look without the GUI. Run it with
ParaView's Python (Debian: apt install paraview; without a display, under
xvfb-run):

  pvpython scripts/render_field.py FIELDS.xdmf [--field stress_axial]
           [--time T | --step K] [--revolve [DEG]] [--out image.png]
           [--size W H]

--field   a cell or point array of the snapshots (default von_mises; the
          arrays are listed when the name is not one of them)
--time    the snapshot nearest T seconds; --step the K-th (0: the initial
          state); default the last
--revolve an axisymmetric deck's snapshots (quadrilaterals in the x-y plane,
          x the radius, y the axis) revolved about the axis through DEG
          degrees (default 270: the cut shows the inside), drawn upright
--out     default: the snapshot file's name with _<field>.png

The path is made absolute before ParaView opens it: ParaView 5.11's XDMF 3
readers look for the .h5 beside a bare file name at "<name>.xdmf<name>.h5"
and abort. A 2D mesh is turned into its surface before it is revolved:
Rotational Extrusion takes polygon data only ("vtkPolyData is required").
Exit codes: 0 written, 2 bad arguments or a field/time the file does not
have, 3 a file ParaView cannot read.
"""
import argparse
import os
import sys


def fail(code, message):
    print(f"render_field.py: {message}", file=sys.stderr)
    sys.exit(code)


def main():
    ap = argparse.ArgumentParser(prog="render_field.py", description=__doc__.split("\n\n")[0])
    ap.add_argument("xdmf")
    ap.add_argument("--field", default="von_mises")
    when = ap.add_mutually_exclusive_group()
    when.add_argument("--time", type=float)
    when.add_argument("--step", type=int)
    ap.add_argument("--revolve", nargs="?", const=270.0, type=float, metavar="DEG")
    ap.add_argument("--out")
    ap.add_argument("--size", nargs=2, type=int, default=[900, 900], metavar=("W", "H"))
    args = ap.parse_args()
    path = os.path.abspath(args.xdmf)
    if not os.path.isfile(path):
        fail(2, f"{args.xdmf}: no such file")
    if args.revolve is not None and not 0.0 < args.revolve <= 360.0:
        fail(2, f"--revolve {args.revolve:g}: an angle in (0, 360] degrees")
    if min(args.size) < 16 or max(args.size) > 8192:
        fail(2, f"--size {args.size[0]} {args.size[1]}: 16 to 8192 pixels each way")

    from paraview import simple as pv

    reader = pv.Xdmf3ReaderS(FileName=[path])
    times = list(reader.TimestepValues) if reader.TimestepValues else [0.0]
    if args.step is not None:
        if not -len(times) <= args.step < len(times):
            fail(2, f"--step {args.step}: the file has snapshots 0 to {len(times) - 1}")
        t = times[args.step]
    elif args.time is not None:
        t = min(times, key=lambda x: abs(x - args.time))
    else:
        t = times[-1]
    cells, points = list(reader.CellArrays), list(reader.PointArrays)
    if args.field not in cells + points:
        fail(2, f"--field {args.field}: the snapshots have {', '.join(cells + points)}")
    reader.UpdatePipeline(t)
    info = reader.GetDataInformation()
    if info.GetNumberOfCells() == 0:
        fail(3, f"{args.xdmf}: ParaView read no cells at t = {t:g} s")
    shown = reader
    if args.revolve is not None:
        bounds = info.GetBounds()
        if abs(bounds[4]) > 1e-12 or abs(bounds[5]) > 1e-12 or bounds[0] < -1e-12:
            fail(2, "--revolve: the mesh is not an axisymmetric deck's (x >= 0 the radius, y the axis, z = 0)")
        # y (the axis) onto z, which Rotational Extrusion revolves about.
        upright = pv.Transform(Input=reader)
        upright.Transform.Rotate = [90.0, 0.0, 0.0]
        surface = pv.ExtractSurface(Input=upright)
        shown = pv.RotationalExtrusion(Input=surface)
        shown.Resolution = max(12, int(round(args.revolve / 5.0)))
        shown.Angle = args.revolve
        shown.UpdatePipeline(t)
    view = pv.GetActiveViewOrCreate("RenderView")
    view.ViewSize = args.size
    view.ViewTime = t
    view.OrientationAxesVisibility = 1
    display = pv.Show(shown, view)
    association = "CELLS" if args.field in cells else "POINTS"
    pv.ColorBy(display, (association, args.field))
    display.RescaleTransferFunctionToDataRange(True, False)
    display.SetScalarBarVisibility(view, True)
    bar = pv.GetScalarBar(pv.GetColorTransferFunction(args.field), view)
    bar.Title = f"{args.field}, t = {1e6 * t:.1f} µs"
    if args.revolve is not None:
        view.CameraPosition = [1.0, -1.5, 0.6]
        view.CameraFocalPoint = [0.0, 0.0, 0.0]
        view.CameraViewUp = [0.0, 0.0, 1.0]
    else:
        view.CameraPosition = [0.0, 0.0, 1.0]
        view.CameraFocalPoint = [0.0, 0.0, 0.0]
        view.CameraViewUp = [0.0, 1.0, 0.0]
    view.ResetCamera()
    out = args.out or os.path.splitext(path)[0] + f"_{args.field}.png"
    pv.SaveScreenshot(out, view, ImageResolution=args.size)
    data = shown.GetDataInformation()
    print(f"{out}: {args.field} at t = {t:.6g} s, {data.GetNumberOfCells()} cells drawn")


if __name__ == "__main__":
    main()
