/***************************************************************************
  multiviewdock.h - the Multiview: 1-6 image views of one station
  -------------------------------------------------------------------------
  Navigation along the run (first, -10, previous, station list, next, +10,
  last; PageUp/PageDown, Ctrl for 10, Home/End), 1-6 views in a grid (or
  each in its own dock), a shared cursor readout (image, col/row, value),
  the camera panel (IO and EO of the images shown, with sigmas) and the
  message panel (vertices with XYZ, sigma, residuals, ray angle; warnings).
  Measuring: click a point in a view, check the proposals in the others
  (click to correct), Return accepts, Backspace takes back, F finishes a
  line or polygon, Escape cancels. Tracing (the Trace bar's toggle): a
  click or drag on a road line traces it through the run, drawn in every
  view as it grows; Escape stops (again: drops the line), Backspace takes
  back the last station's part, F writes the line. All the work is done by the session,
  the measurement controller and core; this only wires and draws.
 ***************************************************************************/
#ifndef GEOSTATIONMULTIVIEWDOCK_H
#define GEOSTATIONMULTIVIEWDOCK_H

#include <optional>

#include <QElapsedTimer>
#include <QPointer>
#include <QVector>

#include <qgsdockwidget.h>

class QComboBox;
class QgsCoordinateReferenceSystem;
class QgsGeometry;
class QGridLayout;
class QLabel;
class QPlainTextEdit;
class QSpinBox;
class QTableWidget;
class QTimer;
class QToolButton;
class GeoStationCameraPanel;
class GeoStationImageView;
class GeoStationMeasurementController;
class GeoStationMeasurementStore;
class GeoStationMultiviewSession;
class GeoStationTraceBar;
class GeoStationTraceController;

class GeoStationMultiviewDock : public QgsDockWidget
{
    Q_OBJECT
    Q_PROPERTY( double lastNavigationMs READ lastNavigationMs )
    Q_PROPERTY( double lastProposalMs READ lastProposalMs )

  public:
    //! `trace` may be nullptr: no Trace tool.
    GeoStationMultiviewDock( GeoStationMultiviewSession *session, GeoStationMeasurementController *controller, GeoStationMeasurementStore *store,
                             QWidget *parent = nullptr, GeoStationTraceController *trace = nullptr );
    ~GeoStationMultiviewDock() override;

    GeoStationImageView *view( int index ) const { return mViews.value( index ); }
    int viewCount() const { return mViews.size(); }
    //! Milliseconds from the last station change until every view had drawn its image.
    double lastNavigationMs() const { return mLastNavigationMs; }
    //! Milliseconds from the last reference click to the curves and proposals on screen.
    double lastProposalMs() const { return mLastProposalMs; }

  public slots:
    void firstStation();
    void lastStation();
    void nextStation();
    void previousStation();
    void stepStations( int step );
    //! By id, or the nearest time for an ISO 8601 time; false if nothing matches.
    bool goToStation( const QString &idOrTime );
    //! Views in their own docks (true) or in the grid (false).
    void setSeparateDocks( bool separate );
    QString messagesText() const;
    QWidget *viewWidget( int index ) const;
    //! Zooms a view around a pixel (scripts, tests).
    void zoomViewToPixel( int view, double col, double row, double halfWidthPx );
    //! Shows an image in a view.
    bool setViewImage( int view, const QString &imageId );
    /**
     * Shows a map revision's change in the views (any CRS; null geometries
     * draw nothing, both null clear it): the map's old course dashed red,
     * the new course green, each view zoomed to it. Views whose image does
     * not see the change are given the images that see it best.
     */
    void showChange( const QgsGeometry &oldCourse, const QgsGeometry &newCourse, const QgsCoordinateReferenceSystem &crs );
    void setViewEnhancement( int view, const QString &method );

    void appendMessage( const QString &text, bool warning );

    /**
     * While on, clicks in the views go to imagePixelPicked() only, not to
     * the measurement or the Trace tool (the orientation dock measures
     * control points in the photo).
     */
    void setPickingRedirected( bool redirected ) { mPickingRedirected = redirected; }
    bool pickingRedirected() const { return mPickingRedirected; }

  protected:
    //! The keys of the Multiview, taken before the image canvases (which zoom with PgUp/PgDown) see them.
    bool eventFilter( QObject *watched, QEvent *event ) override;

  signals:
    //! Every view has drawn its image after a station change (milliseconds since the change).
    void stationShown( double milliseconds );
    //! A click in a view while the picking is redirected (setPickingRedirected()).
    void imagePixelPicked( const QString &imageId, QPointF pixelInImage );

  private slots:
    void rebuildViews();
    void showViewImages();
    void updateStationControls();
    void updateMeasurementOverlays();
    void updateFeatureOverlays();
    void scheduleFeatureOverlays();
    void updateCameraPanel();
    void updateClassCombo();
    void updateFeatureStatus();
    void updateTraceOverlays();
    void viewRefreshed();

  private:
    QWidget *buildToolbar();
    QWidget *buildMeasureBar();
    bool tracing() const;
    //! A click (or drag: `to` set) in a view, to the measurement or the Trace tool.
    void picked( int view, const QPointF &from, const std::optional<QPointF> &to );
    //! The action of a key in the Multiview, or nothing.
    std::function<void()> keyAction( int key, Qt::KeyboardModifiers modifiers );
    void layoutViews();

    GeoStationMultiviewSession *mSession;
    GeoStationMeasurementController *mController;
    GeoStationMeasurementStore *mStore;
    GeoStationTraceController *mTrace = nullptr;
    GeoStationTraceBar *mTraceBar = nullptr;
    QVector<GeoStationImageView *> mViews;
    QList<QPointer<QgsDockWidget>> mViewDocks;
    bool mSeparateDocks = false;
    bool mPickingRedirected = false;
    QWidget *mViewArea = nullptr;
    QGridLayout *mGrid = nullptr;
    QComboBox *mStationCombo = nullptr;
    QSpinBox *mViewCountSpin = nullptr;
    QComboBox *mClassCombo = nullptr;
    QLabel *mFeatureStatus = nullptr;
    QLabel *mCursorLabel = nullptr;
    QPlainTextEdit *mMessages = nullptr;
    GeoStationCameraPanel *mCameraTable = nullptr;
    QTimer *mOverlayTimer = nullptr;
    QElapsedTimer mNavigationTimer;
    int mPendingRefreshes = 0;
    double mLastNavigationMs = 0.0;
    double mLastProposalMs = 0.0;
    QElapsedTimer mProposalTimer;
};

#endif // GEOSTATIONMULTIVIEWDOCK_H
