/***************************************************************************
  processingtables.h - the tables algorithms exchange (docs/conventions.md §6)
  -------------------------------------------------------------------------
  Image observations (point_id, image_id, col, row [, sigma_px]) and ground
  points (point_id, X, Y, Z [, sx, sy, sz, role]) from any QGIS-readable
  table. Field names match case-insensitively; numbers may arrive as text
  (plain CSV). Every problem is one QgsProcessingException naming the table,
  the row and the field.
 ***************************************************************************/
#ifndef PROCESSINGTABLES_H
#define PROCESSINGTABLES_H

#include <functional>
#include <optional>

#include <QPair>
#include <QString>
#include <QVector>

#include <qgsattributes.h>
#include <qgscoordinatereferencesystem.h>
#include <qgsfields.h>

#include <Eigen/Core>

#include "adjustment/controlpoint.h"
#include "extraction/pairmapping.h"
#include "tracing/roadtracer.h"

class QgsFeatureSource;
class QgsProcessingFeedback;
class QgsCoordinateTransformContext;

namespace GeoStationProcessing
{
  struct ObservationRecord
  {
    QString pointId;
    QString imageId;
    Eigen::Vector2d pixel;
    double sigmaPx = 0.0;       //!< 0 when the table has none
    QgsAttributes extra;        //!< the row's other attributes
  };

  struct ObservationTable
  {
    QVector<ObservationRecord> rows;
    QgsFields extraFields;      //!< fields other than the standard ones
    long failedMatches = 0;     //!< rows skipped: their status is a failure (docs/conventions.md §8), they have no col/row
  };

  struct GroundPointRecord
  {
    QString pointId;
    Eigen::Vector3d world;      //!< block CRS, metres
    Eigen::Vector3d sigmaM = Eigen::Vector3d::Zero();
    bool check = false;
  };

  struct FiducialRecord
  {
    QString fiducialId;
    Eigen::Vector2d pixel;
  };

  //! Known positions for import_block's GEOREFERENCE: camera centres by image name, or control points by point id.
  struct KnownPositionTable
  {
    bool cameraCentres = true;                //!< an "image" field: camera centres; else "point_id": control points
    QVector<QPair<QString, Eigen::Vector3d>> rows; //!< name or id, X, Y, Z in the block CRS
  };

  /**
   * Reads a GEOREFERENCE table: image, X, Y, Z (the source model's image
   * names) or point_id, X, Y, Z (its point ids).
   */
  KnownPositionTable readKnownPositions( QgsFeatureSource *source, const QString &what );

  /**
   * Reads fiducial measurements (fiducial_id, col, row). When the table has an
   * image_id field, only the rows of `imageId` are kept.
   */
  QVector<FiducialRecord> readFiducials( QgsFeatureSource *source, const QString &imageId );

  //! Control pairs of a stereo pair from a table point_id, col_left, row_left, col_right, row_right (pixels); throws QgsProcessingException naming a missing field or a bad number.
  std::vector<geostation::ControlPair> readControlPairs( QgsFeatureSource *source );

  //! A road-tracing seed and the row's attributes (kept on the traced line).
  struct TraceSeedRecord
  {
    geostation::TraceSeed seed;
    QgsAttributes attributes;
  };

  //! Seeds from a table seed_id, image_id, col, row [, direction_deg]; names match case-insensitively, numbers may be text; throws QgsProcessingException for a missing field, a bad number or an empty table.
  QVector<TraceSeedRecord> readTraceSeeds( QgsFeatureSource *source );

  //! Reads image observations; `what` names the table in messages.
  ObservationTable readObservations( QgsFeatureSource *source, const QString &what, QgsProcessingFeedback *feedback );

  /**
   * Reads ground points. Coordinates come from the X, Y, Z fields, or else
   * from PointZ geometries transformed to the block CRS.
   */
  //! The terrain height at a block-CRS position, or nothing where it is not known.
  using HeightSource = std::function<std::optional<double>( double x, double y )>;

  /**
   * Ground points (point_id, X, Y, Z fields, or point geometries). With
   * `heightOf`, a point without height (2-D geometry, empty or missing Z)
   * takes the height it gives.
   */
  QVector<GroundPointRecord> readGroundPoints( QgsFeatureSource *source, const QString &what, const QgsCoordinateReferenceSystem &blockCrs,
      const QgsCoordinateTransformContext &transformContext, QgsProcessingFeedback *feedback, const HeightSource &heightOf = HeightSource() );
}

#endif // PROCESSINGTABLES_H
