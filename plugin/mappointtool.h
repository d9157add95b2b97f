/***************************************************************************
  mappointtool.h - a map tool of the QGIS canvas that picks a point
  -------------------------------------------------------------------------
  Only emits the clicked point (canvas CRS), as the georeferencer's tools
  do. The Overview uses it to pick the station nearest the click; the
  orientation dock gives the point a height and makes it a control point.
 ***************************************************************************/
#ifndef GEOSTATIONMAPPOINTTOOL_H
#define GEOSTATIONMAPPOINTTOOL_H

#include <qgsmaptool.h>
#include <qgspointxy.h>

class QgsMapCanvas;
class QgsMapMouseEvent;

class GeoStationMapPointTool : public QgsMapTool
{
    Q_OBJECT

  public:
    //! \a cursor: e.g. Qt::PointingHandCursor to pick a station, Qt::CrossCursor to place a ground point
    GeoStationMapPointTool( QgsMapCanvas *canvas, Qt::CursorShape cursor );
    void canvasReleaseEvent( QgsMapMouseEvent *e ) override;

  signals:
    void picked( const QgsPointXY &pointInCanvasCrs );
};

#endif // GEOSTATIONMAPPOINTTOOL_H
