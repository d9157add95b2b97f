/***************************************************************************
  groundpointtool.h - a map tool of the QGIS canvas: pick a ground point
  -------------------------------------------------------------------------
  Only emits the clicked point (canvas CRS), as the georeferencer's tools
  do; the orientation dock gives it a height and a control point.
 ***************************************************************************/
#ifndef GEOSTATIONGROUNDPOINTTOOL_H
#define GEOSTATIONGROUNDPOINTTOOL_H

#include <qgsmaptool.h>
#include <qgspointxy.h>

class QgsMapCanvas;
class QgsMapMouseEvent;

class GeoStationGroundPointTool : public QgsMapTool
{
    Q_OBJECT

  public:
    explicit GeoStationGroundPointTool( QgsMapCanvas *canvas );
    void canvasReleaseEvent( QgsMapMouseEvent *e ) override;

  signals:
    void picked( const QgsPointXY &pointInCanvasCrs );
};

#endif // GEOSTATIONGROUNDPOINTTOOL_H
