/***************************************************************************
  geometryprojector.h - a map geometry into one image, for project_to_image
  -------------------------------------------------------------------------
  Vertices are transformed to the block CRS and, without a Z, draped on the
  DEM; points are projected (with the DEM, the terrain may hide them),
  lines and rings densified, cut or clipped where they leave the
  projectable space (core geometry/lineprojection). Image space: x = col,
  y = -row.
 ***************************************************************************/
#ifndef GEOMETRYPROJECTOR_H
#define GEOMETRYPROJECTOR_H

#include <memory>
#include <optional>
#include <vector>

#include <QString>
#include <qgsabstractgeometry.h>
#include <qgscoordinatetransform.h>
#include <qgsfeatureid.h>
#include <qgslinestring.h>
#include <qgspoint.h>

#include "dem/monoplotter.h"
#include "geometry/lineprojection.h"

namespace GeoStationProcessing
{
  //! Why one feature cannot be projected (the others go on): status no_height, outside_dem or transform_failed, and one sentence.
  struct FeatureProblem
  {
    QString status, message;
  };

  class GeometryProjector
  {
    public:
      /**
       * `monoplotter` (may be null) gives heights to vertices without Z and
       * hides points behind the terrain; `drapeLines`: the heights of the
       * points inserted into lines come from the DEM too (the layer has no Z).
       */
      GeometryProjector( const geostation::OrientedImage &image, const geostation::Monoplotter *monoplotter, const QgsCoordinateTransform &toBlock,
                         double densifyPx, bool drapeLines );

      /**
       * The geometry in the image; nullptr when it cannot be projected
       * (behind the camera, outside the lens field: see `tally`). Throws
       * FeatureProblem when a vertex has no height or cannot be transformed.
       */
      std::unique_ptr<QgsAbstractGeometry> project( const QgsAbstractGeometry *geometry, QgsFeatureId id, geostation::FeatureProjectionTally &tally ) const;

    private:
      Eigen::Vector3d groundOf( const QgsPoint &vertex, QgsFeatureId id ) const;
      std::optional<QgsPoint> projectPoint( const Eigen::Vector3d &ground, geostation::FeatureProjectionTally &tally ) const;
      std::unique_ptr<QgsLineString> projectLine( const QgsLineString &line, QgsFeatureId id, geostation::FeatureProjectionTally &tally, bool closed,
          std::vector<std::unique_ptr<QgsLineString>> *otherParts = nullptr ) const;

      const geostation::OrientedImage &mImage;
      const geostation::Monoplotter *mMonoplotter;
      QgsCoordinateTransform mToBlock;
      geostation::GroundPointViewer mView;
      geostation::GroundLineOptions mLineOptions;
  };

} // namespace GeoStationProcessing

#endif // GEOMETRYPROJECTOR_H
