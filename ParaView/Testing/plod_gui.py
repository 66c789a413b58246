"""Run by the ParaView GUI (paraview --script=plod_gui.py --exit, under xvfb-run): the plugin
loads into the GUI from PV_PLUGIN_PATH, "Perceptual LOD" is in the Representation list of a
surface and draws triangles in the GUI's render view."""
from paraview.simple import Contour, GetActiveViewOrCreate, Render, ResetCamera, Show, Wavelet

view = GetActiveViewOrCreate("RenderView")
contour = Contour(Input=Wavelet(), ContourBy=["POINTS", "RTData"], Isosurfaces=[157.0])
display = Show(contour, view)
types = list(display.GetProperty("Representation").Available)
if "Perceptual LOD" not in types:
    print("FAIL: 'Perceptual LOD' is not among the representations:", types, flush=True)
else:
    display.SetRepresentationType("Perceptual LOD")
    ResetCamera(view)
    Render(view)
    display.UpdatePropertyInformation()
    triangles = display.GetPropertyValue("NumberOfTriangles")
    full = contour.GetDataInformation().GetNumberOfCells()
    if triangles and 0 < triangles < full:
        print("gui: ok (%d of %d triangles drawn)" % (triangles, full), flush=True)
    else:
        print("FAIL: the GUI's render drew %s triangles of %d" % (triangles, full), flush=True)
