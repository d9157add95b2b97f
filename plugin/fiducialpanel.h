/***************************************************************************
  fiducialpanel.h - the inner orientation of a scanned photo, interactive
  -------------------------------------------------------------------------
  The orientation dock's fiducial section (Stokes 1988, §4): the
  corner fiducials detected automatically (template + centre of gravity,
  core), any of them measured or corrected by a click in the photo, and
  the affine result, live: Stokes' (1988) decomposition (A, B, α_A, α_B,
  affinity, β), σ0 and the residuals per fiducial.
 ***************************************************************************/
#ifndef GEOSTATIONFIDUCIALPANEL_H
#define GEOSTATIONFIDUCIALPANEL_H

#include <array>
#include <memory>
#include <optional>

#include <QPointF>
#include <QWidget>

#include "camera/camera.h"
#include "imageproc/fiducialdetection.h"
#include "io/block.h"
#include "ui_geostationfiducialpanelbase.h"

class GeoStationBackgroundTask;
class GeoStationFiducialModel;

class GeoStationFiducialPanel : public QWidget, private Ui::GeoStationFiducialPanelBase
{
    Q_OBJECT

  public:
    explicit GeoStationFiducialPanel( QWidget *parent = nullptr );

    /**
     * The photo whose fiducials are measured: its camera (with calibrated
     * fiducials), its file, and the inner orientation the block already
     * has for it (used until fiducials are measured here).
     */
    void setPhoto( const geostation::Camera &camera, const QString &imagePath, const std::optional<geostation::ImageInnerOrientation> &existing );
    GeoStationFiducialModel *model() const { return mModel; }
    bool measuring() const;
    //! The inner orientation: measured here when enough fiducials are, else the block's; nothing without either.
    std::optional<geostation::ImageInnerOrientation> innerOrientation() const;
    QString resultText() const;

  public slots:
    /**
     * Starts detecting the corner fiducials in the background (the whole
     * scan's corners are read): progress in message(), the button cancels;
     * detectionFinished() tells how many were found. False when it cannot
     * start (one runs, no pixel size).
     */
    bool detect();
    //! Measures the selected fiducial (else the first not measured) at a pixel of the scan.
    void measurePixel( const QPointF &pixelInScan );
    void selectRow( int row );

  signals:
    void innerOrientationChanged();
    void measuringToggled( bool on );
    void message( const QString &text, bool warning );
    //! Detect Fiducials has ended: how many corners were found (0 when cancelled).
    void detectionFinished( int found );

  private slots:
    void updateResult();
    //! The detected corners measured (or why not said).
    void takeDetection( const QString &error );

  private:
    GeoStationFiducialModel *mModel = nullptr;
    geostation::Camera mCamera;
    QString mImagePath;
    std::optional<geostation::ImageInnerOrientation> mExisting;
    GeoStationBackgroundTask *mDetection = nullptr;
    std::shared_ptr<std::array<geostation::DetectedFiducial, 4>> mDetected; //!< what the running (or last) detection writes
    QString mDetectingPath; //!< the scan the running (or last) detection reads
};

#endif // GEOSTATIONFIDUCIALPANEL_H
