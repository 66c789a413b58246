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
 * It draws the same triangles at the same places as vtkMultiscalePatchGenerator with
 * FoldHandling KEEP, with these differences: back faces are culled by OpenGL
 * (glCullFace) when the selector hid them, where the patch generator tests each triangle
 * against the eye; triangles among hidden (culled) cells are sent and clipped rather than
 * skipped; turned-over triangles (folds) are drawn as they are, not on reversed normals. The
 * mapper's input is made from the octree (do not set one); the octree's cut must come from a
 * vtkPerceptualLODSelector or a vtkMultiscaleOctreeCutter.
 *
 * It needs OpenGL 4.0 (buffer textures of three floats, integer textures, gl_VertexID) and
 * glMultiDrawElements.
 * IsSupported() tells whether a render window has them; vtkPerceptualLODActor falls back to the
 * CPU path with a warning naming the missing feature.
 *
 * @warning Hardware picking and the value pass see the whole surface, not the cut. Ghost flags
 * (PointGhost, a distributed build) are not honoured: every triangle of the cut is drawn, so
 * a distributed build must draw through the CPU path (the ParaView representation always does).
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

  vtkIdType LastUploadBytes = 0;
  vtkIdType LastStateUploadBytes = 0;
  vtkIdType NumberOfDrawnTriangles = 0;
  vtkIdType NumberOfRanges = 0;
  std::string UnsupportedReason;
  std::string SimulatedMissingFeature;

private:
  vtkPerceptualLODMapper(const vtkPerceptualLODMapper&) = delete;
  void operator=(const vtkPerceptualLODMapper&) = delete;

  struct Resident;
  std::unique_ptr<Resident> Internal;
};

#endif
