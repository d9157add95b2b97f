/***************************************************************************
  reviewtool.h - the map tool that accepts or rejects extracted lines
 ***************************************************************************/
#ifndef GEOSTATIONREVIEWTOOL_H
#define GEOSTATIONREVIEWTOOL_H

#include <qgsfeatureid.h>
#include <qgsmaptool.h>

class QgsMapCanvas;
class QgsMapMouseEvent;
class QgsPointXY;
class QgsVectorLayer;

/**
 * Map tool of the QGIS canvas: a left click on an extracted line accepts it,
 * a right click rejects it. Only emits the line found (the nearest line of
 * an extracted-roads layer within the search radius).
 */
class GeoStationReviewTool : public QgsMapTool
{
    Q_OBJECT

  public:
    explicit GeoStationReviewTool( QgsMapCanvas *canvas );
    void canvasReleaseEvent( QgsMapMouseEvent *e ) override;

    //! The nearest line of an extracted-roads layer of the canvas within `radius` (map units) of a map point.
    static bool lineAt( QgsMapCanvas *canvas, const QgsPointXY &pointInCanvasCrs, double radius, QgsVectorLayer *&layer, QgsFeatureId &fid );

  signals:
    void picked( QgsVectorLayer *layer, QgsFeatureId fid, bool accept );
    void missed();
};

#endif // GEOSTATIONREVIEWTOOL_H
