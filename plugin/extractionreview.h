/***************************************************************************
  extractionreview.h - reviewing an extracted road network in QGIS
  -------------------------------------------------------------------------
  geostation:extract_roads writes its 3-D lines (line_id, accepted_in,
  length_m, sigma_max). The operator reviews them on the map: a line
  accepted is copied into the current line class of the measurements
  GeoPackage with method "extracted" (its vertices with the line's sigma_max,
  an upper bound), a line rejected is only marked; either way the
  extracted layer's `review` field records the decision, so the operator
  sees what is left. Accepting twice does nothing.
 ***************************************************************************/
#ifndef GEOSTATIONEXTRACTIONREVIEW_H
#define GEOSTATIONEXTRACTIONREVIEW_H

#include <QObject>

#include <qgsfeatureid.h>
#include <qgsmaptool.h>

class QgsVectorLayer;
class GeoStationMeasurementStore;
class GeoStationSession;

class GeoStationExtractionReview : public QObject
{
    Q_OBJECT

  public:
    GeoStationExtractionReview( GeoStationSession *session, GeoStationMeasurementStore *store, QObject *parent = nullptr );

    //! A layer written by geostation:extract_roads (3-D lines with line_id, accepted_in and sigma_max).
    static bool isExtractedRoadsLayer( const QgsVectorLayer *layer );

    /**
     * Accepts (copies into the current line class) or rejects a line of an
     * extracted-roads layer and records the decision in its `review` field.
     * False with a message when nothing was done.
     */
    bool review( QgsVectorLayer *layer, QgsFeatureId fid, bool accept );

  signals:
    void message( const QString &text, bool warning );

  private:
    bool mark( QgsVectorLayer *layer, QgsFeatureId fid, const QString &decision );

    GeoStationSession *mSession;
    GeoStationMeasurementStore *mStore;
};

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

#endif // GEOSTATIONEXTRACTIONREVIEW_H
