"""An independent iso-surface for checking LSW's volume wraps: VTK's reader and marching cubes,
mapped to the file's world frame (NIfTI sform, else qform), written as PLY.

Usage: python3 benches/peers/vtk_iso.py VOLUME.nii.gz ISO OUT.ply   (pip install vtk)
Then:  lsw metrics WRAP.ply --target OUT.ply
"""
import sys

import vtk


def main(path, iso, out):
    reader = vtk.vtkNIFTIImageReader()
    reader.SetFileName(path)
    reader.Update()
    # The reader gives index·spacing coordinates with the origin at 0; the world frame is the
    # sform (or qform) applied to those, as NIfTI defines it.
    matrix = reader.GetSFormMatrix() or reader.GetQFormMatrix()
    mc = vtk.vtkMarchingCubes()
    mc.SetInputConnection(reader.GetOutputPort())
    mc.SetValue(0, float(iso))
    mc.ComputeNormalsOff()
    transform = vtk.vtkTransform()
    if matrix is not None:
        transform.SetMatrix(matrix)
    world = vtk.vtkTransformFilter()
    world.SetTransform(transform)
    world.SetInputConnection(mc.GetOutputPort())
    world.Update()
    writer = vtk.vtkPLYWriter()
    writer.SetFileName(out)
    writer.SetInputConnection(world.GetOutputPort())
    writer.SetFileTypeToBinary()
    writer.Write()
    print(f"{out}: {world.GetOutput().GetNumberOfPoints()} points, {world.GetOutput().GetNumberOfCells()} triangles")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], sys.argv[3])
