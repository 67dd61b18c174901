#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Renders a hex mesh written by om_dthex to a PNG, coloured by the hex scaled Jacobian.

The mesh is cut by a plane through its centre (whole hexes kept, none sliced) so that the
interior elements show beside the boundary; the scaled Jacobian is computed by VTK's
vtkMeshQuality (Verdict), independently of the values om_dthex writes.

    ./build/om_dthex meshes/femur_proximal_ct.off -o /tmp/femur_hex.vtu
    xvfb-run -a python3 tools/render_picture.py /tmp/femur_hex.vtu docs/images/femur_hex.png \
        --title "femur_proximal_ct.off at the defaults, cut open"

Needs VTK 9's Python bindings (Debian: python3-vtk9). Debian's VTK renders through X, so
on a machine without a display run it under xvfb-run (Debian: xvfb).
"""
import argparse
import sys

import vtk


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("mesh", help="hex mesh (.vtu or .vtk) written by om_dthex")
    parser.add_argument("png", help="picture to write")
    parser.add_argument("--size", type=int, nargs=2, default=[860, 760], metavar=("W", "H"))
    parser.add_argument("--title", default=None, help="a first caption line, above the mesh's counts")
    parser.add_argument("--azimuth", type=float, default=35.0, help="camera turn about the view-up axis, degrees")
    parser.add_argument("--elevation", type=float, default=10.0, help="camera tilt, degrees")
    parser.add_argument("--cut", default="auto", choices=["auto", "x", "y", "z", "none"],
                        help="axis normal to the cutting plane; auto (default): the axis of the bounding box's "
                             "shortest side, so the cut shows the largest section; none: the whole boundary")
    args = parser.parse_args()

    reader = vtk.vtkXMLUnstructuredGridReader() if args.mesh.endswith(".vtu") else vtk.vtkUnstructuredGridReader()
    reader.SetFileName(args.mesh)
    reader.Update()
    grid = reader.GetOutput()
    if grid.GetNumberOfCells() == 0:
        sys.exit(f"render_picture: {args.mesh}: no cells")

    quality = vtk.vtkMeshQuality()
    quality.SetInputData(grid)
    quality.SetHexQualityMeasureToScaledJacobian()
    quality.Update()
    measured = quality.GetOutput()
    values = measured.GetCellData().GetArray("Quality")
    lo, hi = values.GetRange()

    bounds = measured.GetBounds()
    extent = [bounds[2 * i + 1] - bounds[2 * i] for i in range(3)]
    centre = [(bounds[2 * i] + bounds[2 * i + 1]) / 2 for i in range(3)]
    longest = max(range(3), key=lambda i: extent[i])
    axis = min(range(3), key=lambda i: extent[i]) if args.cut in ("auto", "none") else "xyz".index(args.cut)
    normal = [0.0, 0.0, 0.0]
    normal[axis] = 1.0
    up = [0.0, 0.0, 0.0]
    up[longest if longest != axis else (axis + 1) % 3] = 1.0

    shown = measured
    if args.cut != "none":
        plane = vtk.vtkPlane()
        plane.SetOrigin(centre)
        plane.SetNormal(normal)
        extract = vtk.vtkExtractGeometry()  # whole hexes on one side of the plane
        extract.SetInputData(measured)
        extract.SetImplicitFunction(plane)
        extract.ExtractInsideOn()  # the side the normal points away from; the camera looks at the cut
        extract.ExtractBoundaryCellsOn()
        extract.Update()
        shown = extract.GetOutput()

    surface = vtk.vtkDataSetSurfaceFilter()
    surface.SetInputData(shown)

    lut = vtk.vtkLookupTable()
    lut.SetNumberOfTableValues(256)
    lut.SetHueRange(0.0, 0.667)  # red (poor) to blue (good)
    lut.SetTableRange(0.0, 1.0)
    lut.Build()

    mapper = vtk.vtkDataSetMapper()
    mapper.SetInputConnection(surface.GetOutputPort())
    mapper.SetScalarModeToUseCellFieldData()
    mapper.SelectColorArray("Quality")
    mapper.SetLookupTable(lut)
    mapper.SetScalarRange(0.0, 1.0)
    actor = vtk.vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().EdgeVisibilityOn()
    actor.GetProperty().SetEdgeColor(0.15, 0.15, 0.15)
    actor.GetProperty().SetLineWidth(0.5)

    bar = vtk.vtkScalarBarActor()
    bar.SetLookupTable(lut)
    bar.SetTitle("scaled Jacobian")
    bar.SetNumberOfLabels(6)
    bar.SetLabelFormat("%.1f")
    bar.SetPosition(0.8, 0.12)
    bar.SetWidth(0.1)
    bar.SetHeight(0.76)
    bar.UnconstrainedFontSizeOn()
    for prop, size in ((bar.GetTitleTextProperty(), 20), (bar.GetLabelTextProperty(), 18)):
        prop.SetColor(0.1, 0.1, 0.1)
        prop.SetFontSize(size)
        prop.ItalicOff()
        prop.ShadowOff()
        prop.BoldOff()

    renderer = vtk.vtkRenderer()
    renderer.SetBackground(1.0, 1.0, 1.0)
    renderer.AddActor(actor)
    renderer.AddActor2D(bar)
    text = vtk.vtkTextActor()
    caption = (f"{grid.GetNumberOfCells():,} hexes, {grid.GetNumberOfPoints():,} nodes; "
               f"scaled Jacobian {lo:.3f} to {hi:.3f}")
    if args.title:
        caption = args.title + "\n" + caption
    text.SetInput(caption)
    text.GetTextProperty().SetColor(0.1, 0.1, 0.1)
    text.GetTextProperty().SetFontSize(20)
    text.GetTextProperty().SetVerticalJustificationToTop()
    text.SetPosition(20, args.size[1] - 15)
    renderer.AddActor2D(text)

    window = vtk.vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetSize(*args.size)
    window.AddRenderer(renderer)
    camera = renderer.GetActiveCamera()
    camera.SetFocalPoint(centre)
    camera.SetPosition([centre[i] + normal[i] * max(extent) * 3 for i in range(3)])
    camera.SetViewUp(up)
    camera.Azimuth(args.azimuth)
    camera.Elevation(args.elevation)
    renderer.ResetCamera()
    camera.Zoom(0.92)
    window.Render()

    image = vtk.vtkWindowToImageFilter()
    image.SetInput(window)
    image.ReadFrontBufferOff()
    image.Update()
    writer = vtk.vtkPNGWriter()
    writer.SetFileName(args.png)
    writer.SetInputConnection(image.GetOutputPort())
    writer.Write()
    print(f"render_picture: wrote {args.png} ({grid.GetNumberOfCells()} hexes, scaled Jacobian {lo:.4f}..{hi:.4f})")


if __name__ == "__main__":
    main()
