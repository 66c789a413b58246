"""Opening a model file given on the command line, safely: the examples' one check."""
import os
import sys

from perceptual_lod import vtkPLYFileCheck


def checked(path):
    """`path` if a reader may open it: a regular file (a FIFO would make the reader wait forever)
    that, for PLY, vtkPLYFileCheck accepts (VTK's PLY reader crashes on some damaged files).
    Otherwise the program exits with a message saying what is wrong."""
    if not os.path.isfile(path):
        sys.exit(f'{path}: missing, or not a regular file (a directory, a FIFO or a device)')
    if path.lower().endswith('.ply'):
        check = vtkPLYFileCheck()
        check.SetFileName(path)
        if not check.Check():
            sys.exit(f'{path}: {check.GetErrorMessage()}')
    return path
