/***************************************************************************
  geometryprojector.h - a map geometry into one image, for project_to_image
  -------------------------------------------------------------------------
  Vertices are transformed to the block CRS; the rest is core's one rule
  for a map feature in a photo (dem/featureinphoto): heights from the
  feature's Z, else the DEM; points projected (with the DEM, the terrain may
  hide them), lines and rings densified, cut or clipped where they leave
  the projectable space. Image space: x = col, y = -row
  (geometry/imagespace.h).
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

#include "dem/featureinphoto.h"

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
       * `monoplotter` (may be null) gives heights to vertices without Z (and
       * to the points inserted into lines whose vertices all took theirs
       * from it) and hides points behind the terrain.
       */
      GeometryProjector( const geostation::OrientedImage &image, const geostation::Monoplotter *monoplotter, const QgsCoordinateTransform &toBlock,
                         double densifyPx );

      /**
       * The geometry in the image; nullptr when it cannot be projected
       * (behind the camera, outside the lens field: see `tally`). Throws
       * FeatureProblem when a vertex has no height or cannot be transformed.
       */
      std::unique_ptr<QgsAbstractGeometry> project( const QgsAbstractGeometry *geometry, QgsFeatureId id, geostation::FeatureProjectionTally &tally ) const;

    private:
      geostation::GroundPart groundOf( const QgsAbstractGeometry &part, QgsFeatureId id ) const;
      std::optional<QgsPoint> projectPoint( const QgsPoint &point, QgsFeatureId id, geostation::FeatureProjectionTally &tally ) const;
      std::unique_ptr<QgsLineString> projectLine( const QgsLineString &line, QgsFeatureId id, geostation::FeatureProjectionTally &tally, bool closed,
          std::vector<std::unique_ptr<QgsLineString>> *otherParts = nullptr ) const;

      const geostation::OrientedImage &mImage;
      QgsCoordinateTransform mToBlock;
      geostation::FeatureHeights mHeights;
      double mDensifyPx;
  };

} // namespace GeoStationProcessing

#endif // GEOMETRYPROJECTOR_H
