// SPDX-License-Identifier: BSD-3-Clause
#include "vtkPerceptualLODMapper.h"

#include "plodCut.h"
#include "plodOctree.h"
#include "plodPatches.h"

#include "vtkAlgorithm.h"
#include "vtkAlgorithmOutput.h"
#include "vtkCellArray.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkMultiscaleOctree.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkOpenGLBufferObject.h"
#include "vtkOpenGLIndexBufferObject.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOpenGLState.h"
#include "vtkOpenGLVertexBufferObject.h"
#include "vtkOpenGLVertexBufferObjectGroup.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkRenderer.h"
#include "vtkShader.h"
#include "vtkShaderProgram.h"
#include "vtkSmartPointer.h"
#include "vtkTextureObject.h"
#include "vtkTypeInt32Array.h"
#include "vtkUnsignedCharArray.h"
#include "vtk_glew.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <chrono>
#include <cmath>
#include <vector>

vtkStandardNewMacro(vtkPerceptualLODMapper);

namespace
{
/// Seconds on a monotonic clock.
double Now()
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

/// One array of the octree on the GPU: a buffer object seen by the shader as a buffer texture.
struct DeviceArray
{
  vtkNew<vtkOpenGLBufferObject> Buffer;
  vtkNew<vtkTextureObject> Texture;
  const char* Uniform = "";

  /// Uploads `values` values of `components` of VTK type `type`; the bytes sent.
  vtkIdType Upload(vtkOpenGLRenderWindow* window, const void* data, vtkIdType values,
    int components, int type, int bytesPerValue)
  {
    this->Texture->SetContext(window);
    // integer textures for indices and states (the shader reads exact values), three floats
    // for vertices and normals
    const bool integer = type != VTK_FLOAT;
    this->Texture->SetInternalFormat(type == VTK_INT ? GL_R32I
        : type == VTK_UNSIGNED_CHAR                  ? GL_R8UI
                                                     : GL_RGB32F);
    this->Texture->SetFormat(integer ? GL_RED_INTEGER : GL_RGB);
    this->Buffer->SetType(vtkOpenGLBufferObject::TextureBuffer);
    const size_t bytes = static_cast<size_t>(std::max<vtkIdType>(values, 1)) * bytesPerValue;
    std::vector<unsigned char> zero;
    if (values == 0)
    {
      zero.assign(bytes, 0); // a texture needs a value
      data = zero.data();
    }
    this->Buffer->Upload(
      static_cast<const unsigned char*>(data), bytes, vtkOpenGLBufferObject::TextureBuffer);
    this->Texture->CreateTextureBuffer(
      static_cast<unsigned int>(std::max<vtkIdType>(values, 1) / std::max(1, components)),
      components, type, this->Buffer);
    return static_cast<vtkIdType>(bytes);
  }

  void Release(vtkWindow* window)
  {
    this->Texture->ReleaseGraphicsResources(window);
    this->Buffer->ReleaseGraphicsResources();
  }
};
}

struct vtkPerceptualLODMapper::Resident
{
  vtkSmartPointer<vtkAlgorithmOutput> Octree;
  // the surface the base class uploads once per octree: points (world), normals, triangles
  vtkNew<vtkPolyData> Surface;
  vtkMTimeType SurfaceStamp = 0;
  double Origin[3] = { 0, 0, 0 };
  // the cluster tree and the cut state, as buffer textures
  enum
  {
    PointCluster,
    ClusterNode,
    ClusterParent,
    ClusterVertex,
    ClusterNormal,
    State,
    Count
  };
  DeviceArray Arrays[Count];
  bool ResidentValid = false;
  std::vector<uint8_t> Uploaded; // the cut state as the GPU has it
  std::vector<std::pair<int64_t, int64_t>> Spans;
  // this frame
  plod::OctreeView View;
  const uint8_t* Cut = nullptr;
  bool Drawable = false;
  bool CullBackFaces = false;
  std::vector<int64_t> First, Counts;
  // the cut of the last frame drawn (octree stamp, cut array's time and address) and whether
  // this frame's differs
  std::array<vtkMTimeType, 3> CutKey = {};
  bool CutChanged = true;
  // with ghosts: GhostLedBefore[t], the triangles before t whose lead corner is a ghost (they
  // are uploaded as points); empty without ghosts
  std::vector<int64_t> GhostLedBefore;
  std::vector<GLsizei> DrawCounts;
  std::vector<const void*> DrawOffsets;
  plod::PatchWorkspace Workspace;

  Resident()
  {
    const char* names[Count] = { "plodPointCluster", "plodClusterNode", "plodClusterParent",
      "plodClusterVertex", "plodClusterNormal", "plodState" };
    for (int k = 0; k < Count; ++k)
    {
      this->Arrays[k].Uniform = names[k];
    }
  }
};

//------------------------------------------------------------------------------
vtkPerceptualLODMapper::vtkPerceptualLODMapper()
  : Internal(new Resident)
{
  this->SetInputData(this->Internal->Surface);
  this->ScalarVisibilityOff();
}

//------------------------------------------------------------------------------
vtkPerceptualLODMapper::~vtkPerceptualLODMapper() = default;

//------------------------------------------------------------------------------
void vtkPerceptualLODMapper::SetOctreeConnection(vtkAlgorithmOutput* octree)
{
  if (this->Internal->Octree != octree)
  {
    this->Internal->Octree = octree;
    this->Modified();
  }
}

//------------------------------------------------------------------------------
void vtkPerceptualLODMapper::SetSimulatedMissingFeature(const char* feature)
{
  this->SimulatedMissingFeature = feature ? feature : "";
  this->Modified();
}

//------------------------------------------------------------------------------
bool vtkPerceptualLODMapper::IsSupported(vtkRenderWindow* window)
{
  this->UnsupportedReason.clear();
  auto* gl = vtkOpenGLRenderWindow::SafeDownCast(window);
  if (!this->SimulatedMissingFeature.empty())
  {
    this->UnsupportedReason = this->SimulatedMissingFeature;
    return false;
  }
  if (!gl)
  {
    this->UnsupportedReason = "an OpenGL render window";
    return false;
  }
  int major = 0, minor = 0;
  gl->GetOpenGLVersion(major, minor);
  if (major < 4)
  {
    this->UnsupportedReason = "OpenGL 4.0 (buffer textures of three floats; the context has " +
      std::to_string(major) + "." + std::to_string(minor) + ")";
    return false;
  }
  return true;
}

//------------------------------------------------------------------------------
void vtkPerceptualLODMapper::SetSimulatedRendererName(const char* name)
{
  this->SimulatedRendererName = name ? name : "";
}

//------------------------------------------------------------------------------
bool vtkPerceptualLODMapper::IsSoftwareRenderer(vtkRenderWindow* window)
{
  // the context's renderer does not change: read once per window (the actor asks every frame)
  if (this->SimulatedRendererName.empty() && window && window == this->RendererWindow)
  {
    return this->SoftwareRenderer;
  }
  this->RendererWindow = nullptr;
  this->RendererName = this->SimulatedRendererName;
  if (this->RendererName.empty())
  {
    auto* gl = vtkOpenGLRenderWindow::SafeDownCast(window);
    if (!gl || gl->GetNeverRendered())
    {
      return false;
    }
    gl->MakeCurrent();
    const GLubyte* name = glGetString(GL_RENDERER);
    this->RendererName = name ? reinterpret_cast<const char*>(name) : "";
    this->RendererWindow = window;
  }
  this->SoftwareRenderer = IsSoftwareRendererName(this->RendererName);
  return this->SoftwareRenderer;
}

//------------------------------------------------------------------------------
bool vtkPerceptualLODMapper::IsSoftwareRendererName(const std::string& name)
{
  std::string lower = name;
  std::transform(lower.begin(), lower.end(), lower.begin(),
    [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  for (const char* software : { "llvmpipe", "softpipe", "swrast", "software rasterizer",
         "swiftshader", "basic render driver", "gdi generic" })
  {
    if (lower.find(software) != std::string::npos)
    {
      return true;
    }
  }
  return false;
}

//------------------------------------------------------------------------------
vtkMultiscaleOctree* vtkPerceptualLODMapper::UpdateOctree()
{
  Resident& r = *this->Internal;
  vtkAlgorithm* producer = r.Octree ? r.Octree->GetProducer() : nullptr;
  if (!producer)
  {
    vtkErrorMacro("No octree: call SetOctreeConnection with a selector's output port.");
    return nullptr;
  }
  producer->Update(r.Octree->GetIndex());
  auto* octree =
    vtkMultiscaleOctree::SafeDownCast(producer->GetOutputDataObject(r.Octree->GetIndex()));
  if (!octree || octree->GetNumberOfNodes() == 0)
  {
    return nullptr; // nothing to draw
  }
  std::string why;
  vtkMTimeType stamp = 0;
  if (!octree->GetCheckedView(r.View, &stamp, &why))
  {
    vtkErrorMacro("The octree is invalid (" << why << "): nothing drawn.");
    return nullptr;
  }
  // the octree's surface, once per octree
  if (stamp != r.SurfaceStamp)
  {
    this->MakeSurface(octree);
    r.SurfaceStamp = stamp;
    r.ResidentValid = false;
    r.Uploaded.clear();
  }
  return octree;
}

//------------------------------------------------------------------------------
double* vtkPerceptualLODMapper::GetBounds()
{
  this->UpdateOctree();
  return this->Superclass::GetBounds();
}

//------------------------------------------------------------------------------
void vtkPerceptualLODMapper::RenderPiece(vtkRenderer* ren, vtkActor* act)
{
  Resident& r = *this->Internal;
  this->LastUploadBytes = this->LastStateUploadBytes = 0;
  this->NumberOfDrawnTriangles = this->NumberOfRanges = 0;
  this->LastCPUTime = 0;
  r.Drawable = false;
  vtkMultiscaleOctree* octree = this->UpdateOctree();
  const double start = Now(); // after the selector's run, which it times itself
  if (!octree)
  {
    return;
  }
  auto* cut = vtkUnsignedCharArray::SafeDownCast(
    octree->GetNodeData()->GetAbstractArray(vtkMultiscaleOctree::CutStateArrayName()));
  if (!cut || cut->GetNumberOfComponents() != 1 || cut->GetNumberOfTuples() != r.View.NumberOfNodes)
  {
    vtkErrorMacro("The octree has no cut (a CutState array of one value per node): nothing "
                  "drawn.");
    return;
  }
  r.Cut = cut->GetPointer(0);
  // a still frame (the same cut as the last one drawn): nothing to find and nothing to send
  const std::array<vtkMTimeType, 3> cutKey = { r.SurfaceStamp, cut->GetMTime(),
    static_cast<vtkMTimeType>(reinterpret_cast<uintptr_t>(r.Cut)) };
  r.CutChanged = cutKey != r.CutKey;
  std::string why;
  if (r.CutChanged &&
    !plod::DrawnTriangleRanges(r.View, r.Cut, r.First, r.Counts, &why, &r.Workspace))
  {
    r.CutKey = {};
    vtkErrorMacro("Invalid cut: " << why << ". Nothing drawn.");
    return;
  }
  r.CutKey = cutKey;
  // back faces: culled as the selector asked (CutView's last value)
  r.CullBackFaces = false;
  if (vtkFieldData* fd = octree->GetFieldData())
  {
    vtkDataArray* view = fd->GetArray(vtkMultiscaleOctree::CutViewArrayName());
    r.CullBackFaces = view && view->GetNumberOfValues() == 8 && view->GetComponent(7, 0) != 0;
  }
  r.Drawable = true;
  this->LastCPUTime = Now() - start;
  this->Superclass::RenderPiece(ren, act);
}

//------------------------------------------------------------------------------
void vtkPerceptualLODMapper::MakeSurface(vtkMultiscaleOctree* octree)
{
  Resident& r = *this->Internal;
  const plod::OctreeView& v = r.View;
  std::copy(octree->GetOrigin(), octree->GetOrigin() + 3, r.Origin);
  // world points: in double far from the origin (as the patch generator does)
  const double far =
    std::max({ std::abs(v.Origin[0]), std::abs(v.Origin[1]), std::abs(v.Origin[2]) });
  vtkNew<vtkPoints> points;
  points->SetDataType(far > 100.0 * v.RootEdge ? VTK_DOUBLE : VTK_FLOAT);
  points->SetNumberOfPoints(v.NumberOfPoints);
  for (vtkIdType i = 0; i < v.NumberOfPoints; ++i)
  {
    const float* x = &v.Points[3 * i];
    points->SetPoint(i, v.Origin[0] + x[0], v.Origin[1] + x[1], v.Origin[2] + x[2]);
  }
  vtkNew<vtkFloatArray> normals;
  normals->SetName("Normals");
  normals->SetNumberOfComponents(3);
  normals->SetNumberOfTuples(v.NumberOfPoints);
  std::copy(v.Normals, v.Normals + 3 * v.NumberOfPoints, normals->GetPointer(0));
  // the triangles in the octree's (owner) order: a range of them is a range of the IBO
  vtkNew<vtkTypeInt32Array> offsets, connectivity;
  offsets->SetNumberOfValues(v.NumberOfTriangles + 1);
  for (vtkIdType t = 0; t <= v.NumberOfTriangles; ++t)
  {
    offsets->SetValue(t, static_cast<int32_t>(3 * t));
  }
  connectivity->SetNumberOfValues(3 * v.NumberOfTriangles);
  std::copy(v.Triangles, v.Triangles + 3 * v.NumberOfTriangles, connectivity->GetPointer(0));
  vtkNew<vtkCellArray> polys;
  polys->SetData(offsets, connectivity);
  r.Surface->Initialize();
  r.Surface->SetPoints(points);
  r.Surface->GetPointData()->SetNormals(normals);
  r.Surface->SetPolys(polys);
  r.Surface->Modified();
}

//------------------------------------------------------------------------------
void vtkPerceptualLODMapper::BuildIBO(vtkRenderer*, vtkActor*, vtkPolyData*)
{
  // the octree's triangles as they are, one for one, so that a range of the owner-sorted array
  // is a range of the buffer (VTK's own index buffer skips triangles with coincident corners)
  const plod::OctreeView& v = this->Internal->View;
  for (vtkOpenGLHelper& primitive : this->Primitives)
  {
    primitive.IBO->IndexCount = 0;
  }
  std::vector<unsigned int> indices(v.Triangles, v.Triangles + 3 * v.NumberOfTriangles);
  this->CollapseGhostLedTriangles(indices.data());
  vtkOpenGLIndexBufferObject* ibo = this->Primitives[PrimitiveTris].IBO;
  if (!indices.empty())
  {
    ibo->Upload(indices, vtkOpenGLBufferObject::ElementArrayBuffer);
  }
  ibo->IndexCount = indices.size();
}

//------------------------------------------------------------------------------
void vtkPerceptualLODMapper::CollapseGhostLedTriangles(unsigned int* triangles)
{
  Resident& r = *this->Internal;
  const plod::OctreeView& v = r.View;
  r.GhostLedBefore.clear();
  if (!v.PointGhost)
  {
    return;
  }
  // the patch generator's rule: another process draws a triangle whose lead corner (its
  // smallest point index) is a ghost here; all three corners on the lead, it draws nothing
  r.GhostLedBefore.resize(static_cast<size_t>(v.NumberOfTriangles) + 1);
  int64_t ghostLed = 0;
  for (vtkIdType t = 0; t < v.NumberOfTriangles; ++t)
  {
    r.GhostLedBefore[t] = ghostLed;
    unsigned int* c = triangles + 3 * t;
    const unsigned int lead = std::min({ c[0], c[1], c[2] });
    if (v.PointGhost[lead] != 0)
    {
      c[0] = c[1] = c[2] = lead;
      ++ghostLed;
    }
  }
  r.GhostLedBefore[v.NumberOfTriangles] = ghostLed;
}

//------------------------------------------------------------------------------
void vtkPerceptualLODMapper::UploadResident(vtkOpenGLRenderWindow* window)
{
  Resident& r = *this->Internal;
  const plod::OctreeView& v = r.View;
  vtkIdType bytes = 0;
  bytes += r.Arrays[Resident::PointCluster].Upload(
    window, v.PointCluster, v.NumberOfPoints, 1, VTK_INT, 4);
  bytes += r.Arrays[Resident::ClusterNode].Upload(
    window, v.ClusterNode, v.NumberOfClusters, 1, VTK_INT, 4);
  bytes += r.Arrays[Resident::ClusterParent].Upload(
    window, v.ClusterParent, v.NumberOfClusters, 1, VTK_INT, 4);
  bytes += r.Arrays[Resident::ClusterVertex].Upload(
    window, v.ClusterVertex, 3 * v.NumberOfClusters, 3, VTK_FLOAT, 4);
  bytes += r.Arrays[Resident::ClusterNormal].Upload(
    window, v.ClusterNormal, 3 * v.NumberOfClusters, 3, VTK_FLOAT, 4);
  this->LastUploadBytes += bytes;
  r.ResidentValid = true;
}

//------------------------------------------------------------------------------
void vtkPerceptualLODMapper::UploadCut(vtkOpenGLRenderWindow* window)
{
  Resident& r = *this->Internal;
  const int64_t n = r.View.NumberOfNodes;
  DeviceArray& state = r.Arrays[Resident::State];
  vtkIdType bytes = 0;
  if (static_cast<int64_t>(r.Uploaded.size()) != n)
  {
    // the whole state, once per octree
    bytes = state.Upload(window, r.Cut, n, 1, VTK_UNSIGNED_CHAR, 1);
    r.Uploaded.assign(r.Cut, r.Cut + n);
  }
  else if (r.CutChanged)
  {
    // only what changed: spans closer than 64 bytes sent as one
    plod::ChangedSpans(r.Uploaded.data(), r.Cut, n, 64, r.Spans);
    if (!r.Spans.empty())
    {
      state.Buffer->Bind();
      for (const auto& span : r.Spans)
      {
        glBufferSubData(GL_TEXTURE_BUFFER, static_cast<GLintptr>(span.first),
          static_cast<GLsizeiptr>(span.second - span.first), r.Cut + span.first);
        std::copy(r.Cut + span.first, r.Cut + span.second, r.Uploaded.data() + span.first);
        bytes += span.second - span.first;
      }
      state.Buffer->Release();
    }
  }
  this->LastStateUploadBytes = bytes;
  this->LastUploadBytes += bytes;
}

//------------------------------------------------------------------------------
void vtkPerceptualLODMapper::RenderPieceDraw(vtkRenderer* ren, vtkActor* act)
{
  Resident& r = *this->Internal;
  vtkOpenGLHelper& tris = this->Primitives[PrimitiveTris];
  auto* window = vtkOpenGLRenderWindow::SafeDownCast(ren->GetRenderWindow());
  if (!r.Drawable || !window || !tris.IBO || tris.IBO->IndexCount == 0)
  {
    return;
  }
  const double start = Now();
  if (!r.ResidentValid)
  {
    this->UploadResident(window);
  }
  this->UploadCut(window);
  this->LastCPUTime += Now() - start;
  if (r.First.empty())
  {
    return;
  }
  for (DeviceArray& a : r.Arrays)
  {
    a.Texture->Activate();
  }
  this->UpdateShaders(tris, ren, act);
  vtkOpenGLState* gl = window->GetState();
  vtkOpenGLState::ScopedglEnableDisable cull(gl, GL_CULL_FACE);
  if (r.CullBackFaces)
  {
    gl->vtkglEnable(GL_CULL_FACE);
    gl->vtkglCullFace(GL_BACK);
  }
  r.DrawCounts.resize(r.First.size());
  r.DrawOffsets.resize(r.First.size());
  vtkIdType drawn = 0;
  for (size_t i = 0; i < r.First.size(); ++i)
  {
    r.DrawCounts[i] = static_cast<GLsizei>(3 * r.Counts[i]);
    r.DrawOffsets[i] =
      reinterpret_cast<const void*>(static_cast<uintptr_t>(3 * r.First[i] * sizeof(GLuint)));
    drawn += r.Counts[i];
    if (!r.GhostLedBefore.empty())
    {
      drawn -= r.GhostLedBefore[r.First[i] + r.Counts[i]] - r.GhostLedBefore[r.First[i]];
    }
  }
  tris.IBO->Bind();
  glMultiDrawElements(GL_TRIANGLES, r.DrawCounts.data(), GL_UNSIGNED_INT, r.DrawOffsets.data(),
    static_cast<GLsizei>(r.First.size()));
  tris.IBO->Release();
  for (DeviceArray& a : r.Arrays)
  {
    a.Texture->Deactivate();
  }
  this->NumberOfDrawnTriangles = drawn;
  this->NumberOfRanges = static_cast<vtkIdType>(r.First.size());
}

//------------------------------------------------------------------------------
void vtkPerceptualLODMapper::ReplaceShaderValues(
  std::map<vtkShader::Type, vtkShader*> shaders, vtkRenderer* ren, vtkActor* act)
{
  this->Superclass::ReplaceShaderValues(shaders, ren, act);
  std::string vs = shaders[vtkShader::Vertex]->GetSource();
  const bool normals = vs.find("in vec3 normalMC;") != std::string::npos;
  // each corner moved to its representative: the first cluster up from the point's leaf
  // cluster whose node is in the cut (an opened leaf keeps the point and its normal)
  std::string declarations = "in vec4 vertexMC;\n"
                             "uniform isamplerBuffer plodPointCluster;\n"
                             "uniform isamplerBuffer plodClusterNode;\n"
                             "uniform isamplerBuffer plodClusterParent;\n"
                             "uniform samplerBuffer plodClusterVertex;\n"
                             "uniform samplerBuffer plodClusterNormal;\n"
                             "uniform usamplerBuffer plodState;\n"
                             "uniform vec3 plodOffset;\n"
                             "uniform vec3 plodScale;\n"
                             "vec4 plodVertexMC;\n";
  std::string resolve = "  int plodCluster = texelFetch(plodPointCluster, gl_VertexID).r;\n"
                        "  uint plodCut = 0u;\n"
                        "  for (int k = 0; k < 64; ++k)\n"
                        "  {\n"
                        "    plodCut = texelFetch(plodState, texelFetch(plodClusterNode, "
                        "plodCluster).r).r;\n"
                        "    if (plodCut != 0u) break;\n"
                        "    plodCluster = texelFetch(plodClusterParent, plodCluster).r;\n"
                        "  }\n"
                        "  plodVertexMC = plodCut == 3u ? vertexMC : vec4((texelFetch("
                        "plodClusterVertex, plodCluster).xyz + plodOffset) * plodScale, 1.0);\n";
  if (normals)
  {
    declarations += "vec3 plodNormalMC;\n";
    resolve += "  plodNormalMC = plodCut == 3u ? normalMC : "
               "texelFetch(plodClusterNormal, plodCluster).xyz;\n";
  }
  vtkShaderProgram::Substitute(vs, "in vec4 vertexMC;", declarations);
  vtkShaderProgram::Substitute(vs, "//VTK::CustomBegin::Impl", resolve);
  vtkShaderProgram::Substitute(vs, "* vertexMC", "* plodVertexMC", true);
  if (normals)
  {
    vtkShaderProgram::Substitute(vs, "* normalMC", "* plodNormalMC", true);
  }
  shaders[vtkShader::Vertex]->SetSource(vs);
  this->ReplaceFoldRule(shaders[vtkShader::Geometry]);
}

//------------------------------------------------------------------------------
void vtkPerceptualLODMapper::GetShaderTemplate(
  std::map<vtkShader::Type, vtkShader*> shaders, vtkRenderer* ren, vtkActor* act)
{
  this->Superclass::GetShaderTemplate(shaders, ren, act);
  if (this->FoldHandling == 0 || !shaders[vtkShader::Geometry]->GetSource().empty())
  {
    return;
  }
  // a pass-through geometry shader with VTK's tags, so that it sees each triangle's three
  // corners (ReplaceFoldRule fills it in)
  shaders[vtkShader::Geometry]->SetSource("//VTK::System::Dec\n"
                                          "uniform int PrimitiveIDOffset;\n"
                                          "//VTK::PositionVC::Dec\n"
                                          "//VTK::PrimID::Dec\n"
                                          "//VTK::Color::Dec\n"
                                          "//VTK::Normal::Dec\n"
                                          "//VTK::Light::Dec\n"
                                          "//VTK::TCoord::Dec\n"
                                          "//VTK::Picking::Dec\n"
                                          "//VTK::DepthPeeling::Dec\n"
                                          "//VTK::Clip::Dec\n"
                                          "//VTK::Output::Dec\n"
                                          "layout(triangles) in;\n"
                                          "layout(triangle_strip, max_vertices = 3) out;\n"
                                          "void main()\n"
                                          "{\n"
                                          "  //VTK::Normal::Start\n"
                                          "  //PLOD::Fold::Impl\n"
                                          "  for (int i = 0; i < 3; i++)\n"
                                          "  {\n"
                                          "    //VTK::PrimID::Impl\n"
                                          "    //VTK::Clip::Impl\n"
                                          "    //VTK::Color::Impl\n"
                                          "    //VTK::Normal::Impl\n"
                                          "    //VTK::Light::Impl\n"
                                          "    //VTK::TCoord::Impl\n"
                                          "    //VTK::DepthPeeling::Impl\n"
                                          "    //VTK::Picking::Impl\n"
                                          "    //VTK::PositionVC::Impl\n"
                                          "    gl_Position = gl_in[i].gl_Position;\n"
                                          "    EmitVertex();\n"
                                          "  }\n"
                                          "  EndPrimitive();\n"
                                          "}\n");
}

//------------------------------------------------------------------------------
void vtkPerceptualLODMapper::ReplaceFoldRule(vtkShader* geometry)
{
  std::string gs = geometry->GetSource();
  const std::string normal = "normalVCGSOutput = normalVCVSOutput[i];";
  const size_t at = gs.find(normal);
  if (gs.find("//PLOD::Fold::Impl") == std::string::npos)
  {
    return; // not this mapper's geometry shader
  }
  if (at == std::string::npos || gs.find("in vec4 vertexVCVSOutput[];") == std::string::npos)
  {
    // no point normals or no lighting: nothing to decide, no geometry shader
    geometry->SetSource("");
    return;
  }
  // the patch generator's rule (plodPatches.h): turned over when the face normal opposes the
  // normals of all three corners; then reversed (VTK's two-sided lighting turns them back and
  // the fold is lit as the surface facing the viewer) or not emitted
  std::string rule =
    "  vec3 plodFace = cross(vertexVCVSOutput[1].xyz - vertexVCVSOutput[0].xyz,\n"
    "    vertexVCVSOutput[2].xyz - vertexVCVSOutput[0].xyz);\n"
    "  bool plodFold = dot(plodFace, normalVCVSOutput[0]) < 0.0 &&\n"
    "    dot(plodFace, normalVCVSOutput[1]) < 0.0 && dot(plodFace, normalVCVSOutput[2]) < 0.0;\n";
  rule += this->FoldHandling == 1 ? "  if (plodFold) { return; }\n"
                                  : "  float plodTurn = plodFold ? -1.0 : 1.0;\n";
  vtkShaderProgram::Substitute(gs, "//PLOD::Fold::Impl", rule);
  if (this->FoldHandling == 2)
  {
    vtkShaderProgram::Substitute(gs, normal, "normalVCGSOutput = plodTurn * normalVCVSOutput[i];");
  }
  geometry->SetSource(gs);
}

//------------------------------------------------------------------------------
void vtkPerceptualLODMapper::SetMapperShaderParameters(
  vtkOpenGLHelper& cellBO, vtkRenderer* ren, vtkActor* act)
{
  this->Superclass::SetMapperShaderParameters(cellBO, ren, act);
  Resident& r = *this->Internal;
  vtkShaderProgram* program = cellBO.Program;
  if (!program)
  {
    return;
  }
  for (DeviceArray& a : r.Arrays)
  {
    program->SetUniformi(a.Uniform, a.Texture->GetTextureUnit());
  }
  // the VBO's points are (world - shift) * scale: the clusters' octree-local vertices follow
  float offset[3], scale[3];
  vtkOpenGLVertexBufferObject* vbo = this->VBOs->GetVBO("vertexMC");
  const bool shifted = vbo && vbo->GetCoordShiftAndScaleEnabled();
  for (int a = 0; a < 3; ++a)
  {
    offset[a] = static_cast<float>(r.Origin[a] - (shifted ? vbo->GetShift()[a] : 0.0));
    scale[a] = static_cast<float>(shifted ? vbo->GetScale()[a] : 1.0);
  }
  program->SetUniform3f("plodOffset", offset);
  program->SetUniform3f("plodScale", scale);
}

//------------------------------------------------------------------------------
void vtkPerceptualLODMapper::ReleaseGraphicsResources(vtkWindow* window)
{
  Resident& r = *this->Internal;
  for (DeviceArray& a : r.Arrays)
  {
    a.Release(window);
  }
  r.ResidentValid = false;
  r.Uploaded.clear();
  r.CutKey = {};
  this->RendererWindow = nullptr; // its context may go with it
  this->Superclass::ReleaseGraphicsResources(window);
}

//------------------------------------------------------------------------------
void vtkPerceptualLODMapper::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "LastUploadBytes: " << this->LastUploadBytes << "\n";
  os << indent << "LastStateUploadBytes: " << this->LastStateUploadBytes << "\n";
  os << indent << "NumberOfDrawnTriangles: " << this->NumberOfDrawnTriangles << "\n";
  os << indent << "NumberOfRanges: " << this->NumberOfRanges << "\n";
  os << indent << "SimulatedMissingFeature: " << this->SimulatedMissingFeature << "\n";
  os << indent << "RendererName: " << this->RendererName << "\n";
  os << indent << "FoldHandling: " << this->FoldHandling << "\n";
}
