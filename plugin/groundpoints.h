/***************************************************************************
  groundpoints.h - ground positions from QGIS layers for the orientation
  -------------------------------------------------------------------------
  Control points read from a point layer (id from a field point_id, id or
  name, else the feature id; Z from the geometry, a field Z / height /
  elevation, or else the DEM layer), transformed to the block's CRS, and
  the DEM layer's height under a point. Reading only; no maths.
 ***************************************************************************/
#ifndef GEOSTATIONGROUNDPOINTS_H
#define GEOSTATIONGROUNDPOINTS_H

#include <optional>

#include <QList>
#include <QPair>
#include <QString>

#include <Eigen/Core>

#include <qgspointxy.h>

class QgsVectorLayer;
class GeoStationMultiviewSession;

namespace GeoStationGroundPoints
{
  struct ControlLayerPoints
  {
    QList<QPair<QString, Eigen::Vector3d>> points; //!< id, block CRS metres
    int withoutHeight = 0;                        //!< left out: no Z, no height field, not on the DEM layer
  };

  //! The points of a layer in the session's block CRS.
  ControlLayerPoints readControlLayer( QgsVectorLayer *layer, const GeoStationMultiviewSession *session );

  //! The height of the session's DEM layer at a block-CRS point; nothing with the reason in `why`.
  std::optional<double> demHeight( const GeoStationMultiviewSession *session, const QgsPointXY &pointInBlockCrs, QString *why );
} // namespace GeoStationGroundPoints

#endif // GEOSTATIONGROUNDPOINTS_H
