/***************************************************************************
  overviewlayers.h - the run on the QGIS map canvas
  -------------------------------------------------------------------------
  Opening a block adds, on top of the user's layers, a group "GeoStation
  overview" with the trajectory (one line per P-line, in run order), the
  stations (points with id, time, P-line and image count) and the view
  cones of the current station's cameras. The current station is
  highlighted and kept in view. The layers are memory layers rebuilt from
  the block whenever it is opened (also when a project is restored).
 ***************************************************************************/
#ifndef GEOSTATIONOVERVIEWLAYERS_H
#define GEOSTATIONOVERVIEWLAYERS_H

#include <QObject>
#include <QPointer>

#include <qgspoint.h>
#include <qgspointxy.h>
#include <qgsvectorlayer.h>

class QgsMapCanvas;
class QgsProject;
class QgsRubberBand;
class QgsVectorLayer;
class GeoStationMultiviewSession;

class GeoStationOverviewLayers : public QObject
{
    Q_OBJECT

  public:
    GeoStationOverviewLayers( GeoStationMultiviewSession *session, QgsProject *project, QgsMapCanvas *canvas, QObject *parent = nullptr );
    ~GeoStationOverviewLayers() override;

    QgsVectorLayer *trajectoryLayer() const { return mTrajectory; }
    QgsVectorLayer *stationsLayer() const { return mStations; }
    QgsVectorLayer *conesLayer() const { return mCones; }

    //! The station nearest to a point of the map canvas (canvas CRS); -1 if none.
    int stationNearestToMapPoint( const QgsPointXY &pointInCanvasCrs ) const;

    //! Removes the overview layers (block closed, plugin unloaded).
    void removeLayers();

    /**
     * The line being traced (block CRS, as it grows), drawn over the map
     * until it is finished or dropped; empty clears it.
     */
    void setTracedLine( const QVector<QgsPoint> &pointsInBlockCrs );
    //! Vertices of the traced line on the map (tests).
    int tracedLineVertexCount() const { return mTracedVertices; }

  public slots:
    void rebuild();
    void updateCurrentStation();

  private:
    QgsVectorLayer *addLayer( const QString &uri, const QString &name );
    double groundHeightUnder( double x, double y, double cameraZ ) const;

    GeoStationMultiviewSession *mSession;
    QgsProject *mProject;
    QPointer<QgsMapCanvas> mCanvas;
    QPointer<QgsVectorLayer> mTrajectory, mStations, mCones;
    QgsRubberBand *mHighlight = nullptr;
    QgsRubberBand *mTraced = nullptr;
    int mTracedVertices = 0;
};

#endif // GEOSTATIONOVERVIEWLAYERS_H
