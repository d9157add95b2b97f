/***************************************************************************
  measurementoverlay.h - measured features drawn back into the images
  -------------------------------------------------------------------------
  Xin's (1995) consistency check: every feature of the measurement layers
  (edit buffer included) is projected into every image view, so the
  operator sees at once whether what was measured sits on the object, and
  an edit or a deletion in QGIS shows in the views. Core's one rule for a
  map feature in a photo (dem/featureinphoto): lines densified so they
  follow the lens distortion, cut where they leave the part of space the
  camera can see, rings clipped; a vertex without Z lies on Z = 0.
 ***************************************************************************/
#ifndef GEOSTATIONMEASUREMENTOVERLAY_H
#define GEOSTATIONMEASUREMENTOVERLAY_H

#include <QList>
#include <QVector>

#include <qgscoordinatereferencesystem.h>
#include <qgsgeometry.h>

#include "geometry/projection.h"

class QgsVectorLayer;

struct GeoStationOverlayOptions
{
  double maxRangeM = 150.0;  //!< features farther from the camera are not drawn
  double densifyPx = 4.0;
};

/**
 * The features of `layers` as seen in `image`: geometries in pixel space
 * (x = col, y = -row): points, and lines (polygon rings as lines).
 */
QVector<QgsGeometry> projectFeaturesIntoImage( const QList<QgsVectorLayer *> &layers, const geostation::OrientedImage &image,
    const QgsCoordinateReferenceSystem &blockCrs, const GeoStationOverlayOptions &options = GeoStationOverlayOptions() );

/**
 * A 3-D polyline (block CRS) as seen in `image`: a (multi)line in pixel
 * space (x = col, y = -row), null when no part of it is in the frame.
 */
QgsGeometry projectPolylineIntoImage( const std::vector<Eigen::Vector3d> &vertices, const geostation::OrientedImage &image,
                                      const GeoStationOverlayOptions &options = GeoStationOverlayOptions() );

#endif // GEOSTATIONMEASUREMENTOVERLAY_H
