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

class QgsVectorLayer;
class GeoStationMeasurementStore;
class GeoStationMultiviewSession;

class GeoStationExtractionReview : public QObject
{
    Q_OBJECT

  public:
    GeoStationExtractionReview( GeoStationMultiviewSession *session, GeoStationMeasurementStore *store, QObject *parent = nullptr );

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

    GeoStationMultiviewSession *mSession;
    GeoStationMeasurementStore *mStore;
};

#endif // GEOSTATIONEXTRACTIONREVIEW_H
