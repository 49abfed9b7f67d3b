// OCC back end of uvmesh::geom: builds a Model from an OpenCASCADE shape. Available when
// uvmesh is built with UVMESH_BUILD_CAD (the macro UVMESH_HAVE_OCC is then defined).
//
// This header does not include OCCT: TopoDS_Shape is only forward-declared, so code that
// merely passes models around does not pull OCCT in. Callers that own a TopoDS_Shape
// (uvmesh::io's readers) include OCCT themselves.
//
//   TopoDS_Shape shape = ...;                    // e.g. from STEPControl_Reader
//   geom::Model m = geom::model_from_occ(shape, {});
//
// Surfaces evaluate through BRepAdaptor_Surface (face location applied), curves through
// BRepAdaptor_Curve, pcurves through BRep_Tool::CurveOnSurface.
#pragma once

#include "uvmesh/geom/model.h"

class TopoDS_Shape;

namespace uvmesh::geom {

struct OccModelOptions {
  bool check_validity = true;  ///< run BRepCheck per face (Face::valid)
  /// Relative tolerance of detect_singular_sides() for surfaces without analytic poles.
  double pole_rel_tol = 1e-7;
};

/// Builds the model. Throws std::runtime_error (with the failing entity named) when OCC
/// raises; the caller (io) has installed OCC's signal handler.
Model model_from_occ(const TopoDS_Shape& shape, const OccModelOptions& opt);

}  // namespace uvmesh::geom
