#pragma once
// Ray and hit tables of algray-query as CSV.
//   rays: header naming ox,oy,oz,dx,dy,dz,tnear,tfar in any order (other columns are
//         ignored), then one ray per line; numbers as strtod reads them, within double's
//         range; a non-zero direction and 0 <= tnear <= tfar ("inf" allowed for tfar
//         only). A leading UTF-8 byte order mark is skipped. Fields may be quoted as RFC
//         4180 writes them ("ox", "a, b", "say ""hi"""), on one line. An optional column
//         org_error is the origin's uncertainty (RayD::orgError: finite, >= 0).
//   hits: hit,t,nx,ny,nz, one row per ray in input order; zeros on a miss.
#include "algray/embree.h"

#include <iosfwd>
#include <string>
#include <vector>

namespace algray::query {

// A rejected input: "NAME:LINE: message" (LINE 1-based; the column is named in the
// message).
class CsvError : public Error {
 public:
  using Error::Error;
};

// hasOrgError (if given) tells whether the header has the column org_error.
std::vector<RayD> readRays(std::istream& in, const std::string& name, bool* hasOrgError = nullptr);

struct QueryHit {
  bool hit = false;
  double t = 0;
  glm::dvec3 normal{0.0};  // unit length, or zero at a singular point of the surface
};

void writeHits(std::ostream& out, const std::vector<QueryHit>& hits);

}  // namespace algray::query
