/***************************************************************************
  revisionlayers.h - revise_roads' OUTPUT and VERTICES read back for core
  -------------------------------------------------------------------------
  What merge_revisions reads of each pair: the OUTPUT rows as
  core/revision pieces (the map road they belong to - source_fid and
  map_part - made one index shared by every pair; where they lie along it;
  their course) and, for the measured ones, their vertices from the pair's
  VERTICES table (sigma, stereo or terrain height, place along the map).
 ***************************************************************************/
#ifndef REVISIONLAYERS_H
#define REVISIONLAYERS_H

#include <map>
#include <utility>
#include <vector>

#include <qgsfeature.h>

#include "revision/revisionmerge.h"

class QgsVectorLayer;

namespace GeoStationProcessing
{
  //! The map roads met so far: (source_fid, map_part) -> the index core's pieces carry as `road`.
  class MapRoadKeys
  {
    public:
      size_t indexOf( long long sourceFid, int part );
      //! (source_fid, map_part) of an index.
      std::pair<long long, int> keyOf( size_t index ) const { return mKeys.at( index ); }

    private:
      std::map<std::pair<long long, int>, size_t> mIndex;
      std::vector<std::pair<long long, int>> mKeys;
  };

  //! One pair's revision: core's pieces and, per piece, the OUTPUT row it was read from.
  struct RevisionLayer
  {
    geostation::PairRevision revision;
    QgsFeatureList rows;
  };

  /**
   * Reads one pair's OUTPUT (`output`, named by its layer name) and its
   * VERTICES table (`vertices`).
   * Throws QgsProcessingException with one sentence for a layer that is
   * not revise_roads' OUTPUT of this version, an unknown revision, or
   * measured pieces without their vertices.
   */
  RevisionLayer readRevisionLayer( QgsVectorLayer *output, QgsVectorLayer *vertices, MapRoadKeys &keys );
} // namespace GeoStationProcessing

#endif // REVISIONLAYERS_H
