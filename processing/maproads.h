/***************************************************************************
  maproads.h - a road map layer read for core/revision
  -------------------------------------------------------------------------
  The map's lines carried into the block CRS, one road per part of a
  multi-part line, each with the feature it came from; a feature without
  usable geometry is kept as a road without vertices (invalid_geometry).
 ***************************************************************************/
#ifndef MAPROADS_H
#define MAPROADS_H

#include <vector>

#include <Eigen/Core>

#include <qgsfeature.h>
#include <qgsgeometry.h>

#include "revision/maprevision.h"

class QgsCoordinateTransform;
class QgsFeatureSource;
class QgsProcessingFeedback;

namespace GeoStationProcessing
{
  //! The map's roads in the block CRS, with the feature each came from.
  struct MapRoads
  {
    std::vector<geostation::MapRoad> roads;
    std::vector<QgsFeature> source; //!< per road
    std::vector<int> part;          //!< per road: its part of the source feature (from 0)
  };

  /**
   * Reads every feature of `map` through `toBlock`. Heights are taken where
   * the map has them (else NaN: the terrain's); a feature that is NULL,
   * empty or cannot be transformed becomes one road without vertices.
   * Stops early, with what it has read, when the feedback is cancelled.
   */
  MapRoads readMapRoads( QgsFeatureSource &map, const QgsCoordinateTransform &toBlock, QgsProcessingFeedback *feedback );

  //! A LineStringZ through the points; a height that is not finite is written as 0.
  QgsGeometry lineStringZ( const std::vector<Eigen::Vector3d> &points );
}

#endif // MAPROADS_H
