/***************************************************************************
  layerinphoto.h - any map layer drawn in the photo, hidden parts marked
  -------------------------------------------------------------------------
  The monoplotter's map-to-image direction in the GUI: the features of a
  vector layer (points, lines, polygon rings; heights from Z or the DEM
  layer) are projected into the Multiview's views of a photo with the
  current orientation - while it is being measured, not only once saved -
  visible parts solid cyan, parts hidden behind the terrain dashed red
  (core's one rule for a map feature in a photo, dem/featureinphoto, the
  lines split where the terrain hides them). Follows the layer's edits and
  the orientation live (redrawn a moment after a change).
 ***************************************************************************/
#ifndef GEOSTATIONLAYERINPHOTO_H
#define GEOSTATIONLAYERINPHOTO_H

#include <memory>
#include <optional>

#include <QObject>
#include <QPointer>
#include <QTimer>
#include <QVector>

#include <qgsmapcanvas.h>
#include <qgsvectorlayer.h>

#include "dem/monoplotter.h"
#include "geometry/crs.h"

class QgsRubberBand;
class GeoStationMultiviewDock;
class GeoStationMultiviewSession;

class GeoStationLayerInPhoto : public QObject
{
    Q_OBJECT

  public:
    GeoStationLayerInPhoto( GeoStationMultiviewSession *session, GeoStationMultiviewDock *multiview, QObject *parent = nullptr );
    ~GeoStationLayerInPhoto() override;

    //! The layer to show (nullptr: none).
    void setLayer( QgsVectorLayer *layer );
    //! The photo and its current orientation (nothing: not oriented, nothing drawn).
    void setPhoto( const QString &imageId, const std::optional<geostation::OrientedImage> &image );

    //! What the last drawing showed (tests): runs of lines, points, and those hidden by the terrain.
    int visibleParts() const { return mVisibleParts; }
    int hiddenParts() const { return mHiddenParts; }
    //! Features left out (no height: no Z and no DEM under them).
    int skippedFeatures() const { return mSkipped; }

    /**
     * The session's DEM layer as a core monoplotter of the photo (opened once per DEM file), or nullptr without
     * a photo orientation or a readable DEM layer. Valid until the next setPhoto().
     */
    const geostation::Monoplotter *monoplotter();

  public slots:
    //! Draws now.
    void redraw();
    //! Draws a moment later (edits come in bursts).
    void scheduleRedraw();

  private:
    void clear();

    GeoStationMultiviewSession *mSession;
    QPointer<GeoStationMultiviewDock> mMultiview;
    QPointer<QgsVectorLayer> mLayer;
    QString mImageId;
    std::optional<geostation::OrientedImage> mImage;
    QTimer mTimer;
    struct Bands
    {
      QPointer<QgsMapCanvas> canvas;
      QgsRubberBand *visible = nullptr;
      QgsRubberBand *hidden = nullptr;
      QgsRubberBand *visiblePoints = nullptr;
      QgsRubberBand *hiddenPoints = nullptr;
    };
    QVector<Bands> mBands;
    QString mDemPath;
    std::unique_ptr<geostation::Dem> mDem;
    std::unique_ptr<geostation::CrsTransform> mBlockToDem;
    std::unique_ptr<geostation::Monoplotter> mMonoplotter;
    int mVisibleParts = 0, mHiddenParts = 0, mSkipped = 0;
};

#endif // GEOSTATIONLAYERINPHOTO_H
