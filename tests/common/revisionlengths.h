/***************************************************************************
  revisionlengths.h - how much of a map road a revision gave each status,
  for the map-revision tests
 ***************************************************************************/
#ifndef GEOSTATION_TESTS_REVISIONLENGTHS_H
#define GEOSTATION_TESTS_REVISIONLENGTHS_H

#include <utility>

#include "revision/maprevision.h"

namespace geostation::testing
{
  //! The length (XY) of map road `road`'s pieces with `status`, and of all its pieces that are not outside.
  inline std::pair<double, double> lengthOf( const MapRevisionSummary &s, size_t road, RevisionStatus status )
  {
    double with = 0.0, seen = 0.0;
    for ( const RevisedPiece &p : s.pieces )
      if ( p.road == road && p.status != RevisionStatus::Outside )
      {
        seen += p.lengthM();
        if ( p.status == status )
          with += p.lengthM();
      }
    return { with, seen };
  }
} // namespace geostation::testing

#endif // GEOSTATION_TESTS_REVISIONLENGTHS_H
