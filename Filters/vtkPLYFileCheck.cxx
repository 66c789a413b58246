// SPDX-License-Identifier: BSD-3-Clause
#include "vtkPLYFileCheck.h"

#include "plodPLYCheck.h"

#include "vtkObjectFactory.h"

#include <string>

vtkStandardNewMacro(vtkPLYFileCheck);

//------------------------------------------------------------------------------
vtkPLYFileCheck::vtkPLYFileCheck()
  : FileName(nullptr)
  , ReaderLimits(true)
  , ErrorMessage(nullptr)
  , NumberOfVertices(0)
  , NumberOfFaces(0)
  , MaxFaceSize(0)
  , Format(FORMAT_ASCII)
{
}

//------------------------------------------------------------------------------
vtkPLYFileCheck::~vtkPLYFileCheck()
{
  this->SetFileName(nullptr);
  this->SetErrorMessage(nullptr);
}

//------------------------------------------------------------------------------
bool vtkPLYFileCheck::Check()
{
  std::string why;
  plod::PLYSummary summary;
  const bool ok = plod::CheckPLYFile(this->FileName ? this->FileName : "", &why, &summary,
    this->ReaderLimits ? plod::VTKPLYReaderLimits() : plod::PLYReaderLimits());
  this->NumberOfVertices = static_cast<vtkIdType>(summary.NumberOfVertices);
  this->NumberOfFaces = static_cast<vtkIdType>(summary.NumberOfFaces);
  this->MaxFaceSize = static_cast<vtkIdType>(summary.MaxFaceSize);
  this->Format = static_cast<int>(summary.Format);
  this->SetErrorMessage(ok ? nullptr : why.c_str());
  return ok;
}

//------------------------------------------------------------------------------
const char* vtkPLYFileCheck::GetFormatAsString() const
{
  return plod::PLYFormatName(static_cast<plod::PLYFormat>(this->Format));
}

//------------------------------------------------------------------------------
bool vtkPLYFileCheck::CheckFile(const char* path)
{
  return plod::CheckPLYFile(path ? path : "", nullptr, nullptr, plod::VTKPLYReaderLimits());
}

//------------------------------------------------------------------------------
void vtkPLYFileCheck::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "ReaderLimits: " << (this->ReaderLimits ? "On" : "Off") << "\n";
  os << indent << "ErrorMessage: " << this->GetErrorMessage() << "\n";
  os << indent << "NumberOfVertices: " << this->NumberOfVertices << "\n";
  os << indent << "NumberOfFaces: " << this->NumberOfFaces << "\n";
  os << indent << "MaxFaceSize: " << this->MaxFaceSize << "\n";
  os << indent << "Format: " << this->GetFormatAsString() << "\n";
}
