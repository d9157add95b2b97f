/***************************************************************************
  controlpointoverlay.h - the control points drawn in the photo's views
  -------------------------------------------------------------------------
  In every Multiview view that shows the photo being oriented: measured
  points (green cross; red when flagged as a blunder), the semi-automatic
  mode's offers (orange box when found, magenta when flagged) and the
  predictions of points not measured (grey circle).
 ***************************************************************************/
#ifndef GEOSTATIONCONTROLPOINTOVERLAY_H
#define GEOSTATIONCONTROLPOINTOVERLAY_H

#include <QPair>
#include <QPointer>
#include <QString>
#include <QVector>

#include <qgsmapcanvas.h>

class QgsVertexMarker;
class GeoStationControlPointModel;
class GeoStationMultiviewDock;

class GeoStationControlPointOverlay
{
  public:
    GeoStationControlPointOverlay() = default;
    ~GeoStationControlPointOverlay();
    GeoStationControlPointOverlay( const GeoStationControlPointOverlay & ) = delete;
    GeoStationControlPointOverlay &operator=( const GeoStationControlPointOverlay & ) = delete;

    //! Draws the model's points in the views of `multiview` (may be nullptr) that show `imageId`.
    void draw( GeoStationMultiviewDock *multiview, const QString &imageId, const GeoStationControlPointModel &model );
    void clear();
    int markerCount() const { return mMarkers.size(); }

  private:
    //! The markers, with their canvas (which deletes them when it goes first).
    QVector<QPair<QPointer<QgsMapCanvas>, QgsVertexMarker *>> mMarkers;
};

#endif // GEOSTATIONCONTROLPOINTOVERLAY_H
