// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkPerceptualLODMapper
 * @brief   draws a cut of a vtkMultiscaleOctree from data resident on the GPU
 *
 * The GPU draw path. The octree's surface (its points, normals and owner-sorted triangles) is
 * uploaded once per octree, with the cluster tree (each point's leaf cluster, each cluster's
 * node, parent, vertex and normal) as buffer textures. Each frame sends only what the cut
 * changed: the spans of the node state array ("CutState") that differ from the last frame's
 * (plod::ChangedSpans), so a still camera uploads nothing and a small move little. The cut
 * draws a union of ranges of the owner-sorted triangles (plod::DrawnTriangleRanges: those owned
 * by refined nodes and opened leaves), issued as one glMultiDrawElements; the vertex shader moves
 * each corner to its representative by walking the cluster tree up from the point's leaf
 * cluster to the first cluster whose node is in the cut (an opened leaf keeps the point).
 *
 * @code{.cpp}
 * vtkNew<vtkPerceptualLODMapper> mapper;
 * mapper->SetOctreeConnection(selector->GetOutputPort()); // the cut, every frame
 * actor->SetMapper(mapper);
 * @endcode
 *
 * It draws the same triangles at the same places as vtkMultiscalePatchGenerator, with these
 * differences: back faces are culled by OpenGL (glCullFace) when the selector hid them, where
 * the patch generator tests each triangle against the eye; triangles among hidden (culled)
 * cells are sent and clipped rather than skipped. The mapper's input is made from the octree
 * (do not set one); the octree's cut must come from a vtkPerceptualLODSelector or a
 * vtkMultiscaleOctreeCutter.
 *
 * Folds (triangles that clustering turned over, see plodPatches.h) get the patch generator's
 * treatment, decided by a geometry shader from each triangle's three corners: with
 * FOLDS_REVERSE_NORMALS (the default) their normals are reversed, so that they are lit as the
 * surface facing the viewer; with FOLDS_DROP they are not drawn; with FOLDS_KEEP (no geometry
 * shader) they are drawn as they are. The triangle counts do not know folds: dropped folds are
 * counted as drawn.
 *
 * Ghosts (OctreeView::PointGhost, an octree built from a piece of a distributed mesh): a
 * triangle whose lead corner is a ghost is uploaded as a point (its three corners the same),
 * so it draws nothing and is not counted, the patch generator's rule.
 *
 * It needs OpenGL 4.0 (buffer textures of three floats, integer textures, gl_VertexID, geometry
 * shaders) and glMultiDrawElements.
 * IsSupported() tells whether a render window has them; vtkPerceptualLODActor falls back to the
 * CPU path with a warning naming the missing feature.
 *
 * @warning Hardware picking and the value pass see the whole surface, not the cut.
 *
 * @sa vtkPerceptualLODActor vtkMultiscalePatchGenerator vtkPerceptualLODSelector
 */
#ifndef vtkPerceptualLODMapper_h
#define vtkPerceptualLODMapper_h

#include "PerceptualLODRenderingModule.h" // for export macro
#include "vtkOpenGLPolyDataMapper.h"

#include <memory> // for the resident state
#include <string> // for the unsupported reason

class vtkAlgorithmOutput;
class vtkMultiscaleOctree;
class vtkOpenGLRenderWindow;
class vtkRenderWindow;

class PERCEPTUALLODRENDERING_EXPORT vtkPerceptualLODMapper : public vtkOpenGLPolyDataMapper
{
public:
  static vtkPerceptualLODMapper* New();
  vtkTypeMacro(vtkPerceptualLODMapper, vtkOpenGLPolyDataMapper);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// The octree with its cut (a selector's or a cutter's output port), updated every render.
  void SetOctreeConnection(vtkAlgorithmOutput* octree);

  ///@{
  /// Figures of the last render: bytes sent to the GPU (the octree's resident arrays when
  /// they were made, then the changed spans of the cut state), of which the cut state, the
  /// triangles drawn and the ranges they came in.
  vtkGetMacro(LastUploadBytes, vtkIdType);
  vtkGetMacro(LastStateUploadBytes, vtkIdType);
  vtkGetMacro(NumberOfDrawnTriangles, vtkIdType);
  vtkGetMacro(NumberOfRanges, vtkIdType);
  ///@}

  /**
   * The CPU time of the last render, in seconds, less the draw itself and the octree's update
   * (the selector's run, which vtkPerceptualLODSelector::GetSelectTime() gives, and the
   * surface made once per octree): finding the drawn ranges, comparing the cut state with the
   * GPU's copy and handing the changed spans (and, once per octree, the resident arrays) to
   * the driver. With the selector's time it is what the GPU path costs the CPU per frame.
   */
  vtkGetMacro(LastCPUTime, double);

  /**
   * True when `window`'s OpenGL context has what the mapper needs; otherwise false, and
   * GetUnsupportedReason() names the missing feature. The window must have been rendered once.
   */
  bool IsSupported(vtkRenderWindow* window);
  const char* GetUnsupportedReason() { return this->UnsupportedReason.c_str(); }

  /**
   * For tests: act as if the context lacked the named feature (IsSupported then returns false
   * and names it). Empty: no pretence. Default empty.
   */
  void SetSimulatedMissingFeature(const char* feature);

  /**
   * True when `window`'s OpenGL renderer is a software rasterizer (Mesa's llvmpipe, softpipe
   * or swrast, SwiftShader, Microsoft's basic render driver, GDI Generic): there the vertex
   * shader's walk runs on the CPU's cores. The window must have been rendered once.
   * GetRendererName() is the renderer string read.
   */
  bool IsSoftwareRenderer(vtkRenderWindow* window);
  /// Whether an OpenGL renderer string names one of the software rasterizers above.
  static bool IsSoftwareRendererName(const std::string& name);
  const char* GetRendererName() { return this->RendererName.c_str(); }

  /**
   * For tests: act as if the OpenGL renderer string were `name`. Empty: the context's own.
   * Default empty.
   */
  void SetSimulatedRendererName(const char* name);

  ///@{
  /**
   * What to do with folds (triangles clustering turned over), with the values of
   * vtkMultiscalePatchGenerator::FoldHandlings: 0 keep, 1 drop, 2 reverse normals (default).
   * Decided per fragment (see the class documentation).
   */
  vtkSetClampMacro(FoldHandling, int, 0, 2);
  vtkGetMacro(FoldHandling, int);
  ///@}

  void RenderPiece(vtkRenderer* ren, vtkActor* act) override;
  /// The bounds of the octree's surface (the octree is updated first).
  double* GetBounds() override;
  using Superclass::GetBounds;
  void ReleaseGraphicsResources(vtkWindow* window) override;

protected:
  vtkPerceptualLODMapper();
  ~vtkPerceptualLODMapper() override;

  void RenderPieceDraw(vtkRenderer* ren, vtkActor* act) override;
  void ReplaceShaderValues(
    std::map<vtkShader::Type, vtkShader*> shaders, vtkRenderer* ren, vtkActor* act) override;
  void SetMapperShaderParameters(vtkOpenGLHelper& cellBO, vtkRenderer* ren, vtkActor* act) override;
  /// The octree with its cut, updated, with its surface made when the octree changed; null
  /// when there is none (or it is invalid: an error says why).
  vtkMultiscaleOctree* UpdateOctree();
  /// The surface the base class uploads: the octree's points (world), normals and triangles.
  void MakeSurface(vtkMultiscaleOctree* octree);
  /// The cluster tree as buffer textures (once per octree) and the cut's changed spans.
  void UploadResident(vtkOpenGLRenderWindow* window);
  void UploadCut(vtkOpenGLRenderWindow* window);
  /// The triangles' index buffer: the octree's, in its order, ghost-led ones made points.
  void BuildIBO(vtkRenderer* ren, vtkActor* act, vtkPolyData* poly) override;
  /// Ghost-led triangles of `triangles` (the octree's, copied) made points; counts them.
  void CollapseGhostLedTriangles(unsigned int* triangles);
  /// With folds reversed or dropped: a pass-through geometry shader (the rule needs each
  /// triangle's three corners).
  void GetShaderTemplate(
    std::map<vtkShader::Type, vtkShader*> shaders, vtkRenderer* ren, vtkActor* act) override;
  /// The geometry shader's fold rule, as FoldHandling says (none without lighting normals).
  void ReplaceFoldRule(vtkShader* geometry);

  vtkIdType LastUploadBytes = 0;
  vtkIdType LastStateUploadBytes = 0;
  vtkIdType NumberOfDrawnTriangles = 0;
  vtkIdType NumberOfRanges = 0;
  double LastCPUTime = 0;
  std::string UnsupportedReason;
  std::string SimulatedMissingFeature;
  std::string RendererName;
  std::string SimulatedRendererName;
  vtkRenderWindow* RendererWindow = nullptr; // whose renderer RendererName is (not held)
  bool SoftwareRenderer = false;
  int FoldHandling = 2;

private:
  vtkPerceptualLODMapper(const vtkPerceptualLODMapper&) = delete;
  void operator=(const vtkPerceptualLODMapper&) = delete;

  struct Resident;
  std::unique_ptr<Resident> Internal;
};

#endif
