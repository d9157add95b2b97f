/***************************************************************************
  orientationdock.h - orienting one photo interactively
  -------------------------------------------------------------------------
  Stokes' (1988) workflow in a dock: choose the photo (any image
  of the open block, oriented or not), load the control points from a
  point layer or add them, measure each in the photo (clicks in the
  Multiview's view of the photo) and give it a ground position (a click on
  the QGIS map, the height from the DEM layer). Every change re-adjusts
  (the control-point model calls core): residuals in pixels and metres,
  Baarda's w, blunders flagged, σ0 and the parameters with their σ. Once
  oriented, "Predict & Find" offers the points not measured yet (the
  semi-automatic mode), "Refine to Mark" moves a click onto its mark, and
  "Save Orientation to Block" writes the orientation into the block file
  (atomically) with the measurements beside it (<block>.<photo>.control.csv),
  which are read again when the photo is chosen next time.
 ***************************************************************************/
#ifndef GEOSTATIONORIENTATIONDOCK_H
#define GEOSTATIONORIENTATIONDOCK_H

#include <memory>
#include <optional>

#include <QPointer>
#include <QPointF>
#include <QVector>

#include <opencv2/core.hpp>

#include <qgsdockwidget.h>
#include <qgspointxy.h>

#include "dem/demcoverage.h"
#include "geometry/projection.h"
#include "identification/photoidentification.h"
#include "ui_geostationorientationdockbase.h"

class QgsMapCanvas;
class QgsVectorLayer;
class GeoStationControlPointModel;
class GeoStationControlPointOverlay;
class GeoStationBackgroundTask;
class GeoStationFiducialPanel;
class GeoStationLayerInPhoto;
class GeoStationMapPointTool;
class GeoStationMultiviewDock;
class GeoStationMultiviewSession;

class GeoStationOrientationDock : public QgsDockWidget, private Ui::GeoStationOrientationDockBase
{
    Q_OBJECT

  public:
    /**
     * `multiview` (may be nullptr) shows the photo and gives its clicks;
     * `mapCanvas` (may be nullptr) is QGIS's map, for ground positions.
     */
    GeoStationOrientationDock( GeoStationMultiviewSession *session, GeoStationMultiviewDock *multiview, QgsMapCanvas *mapCanvas, QWidget *parent = nullptr );
    ~GeoStationOrientationDock() override;

    GeoStationControlPointModel *model() const { return mModel; }
    GeoStationFiducialPanel *fiducialPanel() const { return mFiducialPanel; }
    QString imageId() const { return mImageId; }
    //! The last message shown (one sentence; problems too).
    QString message() const { return mMessage; }
    QString resultText() const;
    //! The photo's orientation as it stands: the one being measured, else the block's; nothing when neither.
    std::optional<geostation::OrientedImage> currentOrientation() const;
    GeoStationLayerInPhoto *layerInPhoto() const { return mLayerInPhoto; }
    /**
     * How much of the ground seen in the oriented photo the DEM layer covers; nothing without an orientation or a
     * DEM layer. Also a line of the result text, and a warning on Save when the cover is partial.
     */
    const std::optional<geostation::DemCoverageSummary> &demCoverage() const { return mDemCoverage; }
    //! Markers drawn in the views of the photo (tests).
    int markerCount() const;

  public slots:
    //! Chooses the photo to orient; false (with a message) for an unknown image or camera.
    bool setImage( const QString &imageId );
    /**
     * Reads the points of a point layer as control: the id from a field
     * point_id, id or name (else the feature id), Z from the geometry, a
     * field Z / height, or else the DEM layer. Returns how many were read.
     */
    int loadControlLayer( QgsVectorLayer *layer );
    //! Measures the selected point (else the first not measured) at a pixel of the photo; selects the next one.
    void measurePixel( const QPointF &pixelInFile );
    //! Gives the selected point the ground position of a map point (canvas CRS); the height from the DEM layer.
    bool pickGround( const QgsPointXY &pointInCanvasCrs );
    //! Moves the selected measured points onto the centre of their marks; how many moved.
    int refineSelected();
    //! The semi-automatic mode: offers for every point not measured; how many were found.
    int predictAndFind();
    /**
     * Starts identifying the control in the photo with nothing measured (core
     * identifyControlInPhoto(), in the background: progress in the message,
     * the button cancels); identificationFinished() tells how many were
     * offered. False when it cannot start (one runs, no photo).
     */
    bool identifyAutomatically();
    //! Accept Found: every found offer, and the flagged ones whose rows are selected (reviewed by the operator); how many.
    int acceptFound();
    //! Writes the orientation and the measurements; false (with the message) when it cannot.
    bool saveToBlock();
    void selectRow( int row );

  signals:
    void messageShown( const QString &text, bool warning );
    //! Identify Automatically has ended: how many points it offers (0 when cancelled or none identified).
    void identificationFinished( int identified );

  private slots:
    void updateOrientation();
    void updateImageChoices();
    void setMeasuring( bool on );
    void setPickingGround( bool on );
    void updateFreeParameters();
    //! The scan affine of the inner orientation (measured in the fiducial panel, or the block's) to the control-point model.
    void applyInnerOrientation();
    //! The identification's result offered (or its failure said).
    void takeIdentification( const QString &error );

  private:
    void showMessage( const QString &text, bool warning = false );
    //! The photo's file as 8-bit grey (read once per photo); empty with a message when it cannot be read.
    const cv::Mat &photoGrey();
    QList<int> selectedRows() const;
    QString controlTablePath() const;
    void updateCameraLabel();
    void drawMarkers();

    GeoStationMultiviewSession *mSession;
    QPointer<GeoStationMultiviewDock> mMultiview;
    QPointer<QgsMapCanvas> mMapCanvas;
    GeoStationControlPointModel *mModel = nullptr;
    QPointer<GeoStationMapPointTool> mGroundTool;
    QString mImageId;
    QString mMessage;
    std::optional<geostation::DemCoverageSummary> mDemCoverage;
    cv::Mat mGrey;
    QString mGreyImageId;
    std::unique_ptr<GeoStationControlPointOverlay> mOverlay;
    GeoStationLayerInPhoto *mLayerInPhoto = nullptr;
    GeoStationBackgroundTask *mIdentification = nullptr;
    std::shared_ptr<geostation::PhotoIdentificationSummary> mIdentificationResult; //!< what the running (or last) search writes
    QString mIdentifyingImageId; //!< the photo the running (or last) identification searches
};

#endif // GEOSTATIONORIENTATIONDOCK_H
