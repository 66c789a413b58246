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
  , WarningMessage(nullptr)
  , NumberOfVertices(0)
  , NumberOfFaces(0)
  , MaxFaceSize(0)
  , NumberOfShortFaces(0)
  , Format(FORMAT_ASCII)
{
}

//------------------------------------------------------------------------------
vtkPLYFileCheck::~vtkPLYFileCheck()
{
  this->SetFileName(nullptr);
  this->SetErrorMessage(nullptr);
  this->SetWarningMessage(nullptr);
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
  this->NumberOfShortFaces = static_cast<vtkIdType>(summary.NumberOfShortFaces);
  this->Format = static_cast<int>(summary.Format);
  this->SetErrorMessage(ok ? nullptr : why.c_str());
  this->SetWarningMessage(summary.Warning.empty() ? nullptr : summary.Warning.c_str());
  if (!summary.Warning.empty())
  {
    vtkWarningMacro(<< this->FileName << ": " << summary.Warning);
  }
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
  os << indent << "WarningMessage: " << this->GetWarningMessage() << "\n";
  os << indent << "NumberOfVertices: " << this->NumberOfVertices << "\n";
  os << indent << "NumberOfFaces: " << this->NumberOfFaces << "\n";
  os << indent << "MaxFaceSize: " << this->MaxFaceSize << "\n";
  os << indent << "NumberOfShortFaces: " << this->NumberOfShortFaces << "\n";
  os << indent << "Format: " << this->GetFormatAsString() << "\n";
}
