/***************************************************************************
  stationpicktool.h - the Overview's station-picking map tool
 ***************************************************************************/
#ifndef GEOSTATIONSTATIONPICKTOOL_H
#define GEOSTATIONSTATIONPICKTOOL_H

#include <qgsmaptool.h>
#include <qgspointxy.h>

class QgsMapCanvas;
class QgsMapMouseEvent;

/**
 * Map tool of the QGIS canvas: a click picks the nearest station of the
 * run and loads it into the Multiview. Only emits the map point.
 */
class GeoStationStationPickTool : public QgsMapTool
{
    Q_OBJECT

  public:
    explicit GeoStationStationPickTool( QgsMapCanvas *canvas );
    void canvasReleaseEvent( QgsMapMouseEvent *e ) override;

  signals:
    void picked( const QgsPointXY &pointInCanvasCrs );
};

#endif // GEOSTATIONSTATIONPICKTOOL_H
