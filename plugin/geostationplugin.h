/***************************************************************************
  geostationplugin.h - the GeoStation plugin for QGIS desktop
  -------------------------------------------------------------------------
  Thin: the menu, the toolbar and their actions. Everything photogrammetric
  is done by core; the Processing provider is registered here too so the
  toolbox has the algorithms even without the Python bridge.
 ***************************************************************************/
#ifndef GEOSTATIONPLUGIN_H
#define GEOSTATIONPLUGIN_H

#include <memory>

#include <QObject>
#include <QVariantMap>
#include <QPointer>

#include <qgisplugin.h>

class QAction;
class QMenu;
class QToolBar;
class QgisInterface;
class GeoStationTraceController;
class GeoStationExtractionReview;
class GeoStationRevisionDock;
class GeoStationReviewTool;
class GeoStationMeasurementController;
class GeoStationMeasurementStore;
class GeoStationMultiviewDock;
class GeoStationOrientationDock;
class GeoStationOverviewLayers;
class GeoStationMultiviewSession;
class GeoStationMapPointTool;

namespace geostation
{
  class Block;
}

class GeoStationPlugin : public QObject, public QgisPlugin
{
    Q_OBJECT

  public:
    explicit GeoStationPlugin( QgisInterface *iface );
    ~GeoStationPlugin() override;

    void initGui() override;
    void unload() override;

    //! The block opened last, or nullptr.
    const geostation::Block *block() const;
    GeoStationMultiviewSession *session() const { return mSession; }

  public slots:
    /**
     * Opens a block file. Any problem is shown in the message bar as one
     * sentence naming the file and the JSON path; the previously opened block
     * stays open. Returns true on success.
     */
    bool openBlockFile( const QString &path );

    //! Asks for a block file and opens it.
    void openBlock();
    //! Runs geostation:import_block in its dialog and opens the block it writes.
    void importBlock();

    //! Shows the cameras, stations and images of the open block.
    void showBlockInfo();

    //! Opens the Processing dialog of an algorithm (e.g. "geostation:resection").
    void showAlgorithmDialog( const QString &algorithmId );
    //! What an algorithm's dialog starts with: the open block (BLOCK), the first view's image (IMAGE), the first two views' (LEFT, RIGHT).
    QVariantMap dialogDefaults( const QString &algorithmId ) const;

    //! Shows the Multiview dock (created on first use).
    void showMultiview();
    //! Shows the photo orientation dock (created on first use, with the Multiview).
    void showOrientation();
    //! The Review Map Revision panel (geostation:revise_roads' changes into the map).
    void showRevisionReview();
    //! Asks for a photo and its camera (and a new block's file and CRS when none is open), adds it and opens it for orientation.
    void addPhoto();
    /**
     * Adds a photo (scripts, tests): `cameraJson` as in the block file, or
     * empty for a camera of the block of the photo's size or one from the
     * file's EXIF; a new block goes to `newBlockPath` in the project's CRS.
     * Opens the photo in the Multiview and the orientation dock. Returns the
     * image id, or "" with a message in the message bar.
     */
    QString addPhotoFile( const QString &photoPath, const QString &newBlockPath, const QString &cameraJson );
    //! Edits the feature classes in a dialog.
    void editFeatureClasses();
    //! Measurement GeoPackage, DEM layer and road plane in a dialog.
    void editMeasurementSettings();
    //! Asks for coordinates (block CRS), a station id or a time, and goes to the nearest station.
    void goToCoordinate();
    //! GeoStation > User Guide: the installed guide in the web browser (userguide.h), or a warning where it is not installed.
    void openUserGuide();
    //! Goes to the station nearest to X, Y in the block CRS; false if there is none.
    bool goToCoordinateXY( double x, double y );

    // ---- for scripts and tests (also reachable through the GUI) ----
    //! Feature classes as JSON (see GeoStationFeatureClass::toJson); false with a message bar note when invalid.
    bool setFeatureClassesJson( const QString &json );
    void setCurrentClass( const QString &name );
    //! Sets the measurement GeoPackage; false (and a message) if it cannot be written.
    bool setTargetGeoPackage( const QString &path );
    void setDemLayer( const QString &layerId );
    QObject *multiviewDock() const;
    QObject *orientationDock() const;

  signals:
    void blockOpened( const QString &path );

  private:
    QAction *addAction( const QString &objectName, const QString &icon, const QString &text, const QString &tip, void ( GeoStationPlugin::*slot )() );
    //! A menu action (in `menu`) that opens a Processing algorithm's dialog.
    QAction *addAlgorithmAction( QMenu *menu, const QString &objectName, const QString &text, const QString &algorithmId );
    QString blockSummary( const geostation::Block &block ) const;
    //! After Add Photo: the photo in the Multiview and the orientation dock; or the error in the message bar ("" returned).
    QString openAddedPhoto( const QString &imageId, const QString &error );
    void updateActions();
    void writeProject();
    void readProject();

    QgisInterface *mIface = nullptr;
    QPointer<QMenu> mMenu;
    QPointer<QMenu> mAdjustmentMenu;
    QPointer<QToolBar> mToolBar;
    QList<QAction *> mActions;
    QAction *mBlockInfoAction = nullptr;
    QAction *mMultiviewAction = nullptr;
    QAction *mPickStationAction = nullptr;
    bool mRegisteredProvider = false;
    GeoStationMultiviewSession *mSession = nullptr;
    GeoStationMeasurementStore *mStore = nullptr;
    GeoStationMeasurementController *mController = nullptr;
    GeoStationTraceController *mTrace = nullptr;
    GeoStationOverviewLayers *mOverview = nullptr;
    QPointer<GeoStationMultiviewDock> mDock;
    QPointer<GeoStationOrientationDock> mOrientationDock;
    QPointer<GeoStationRevisionDock> mRevisionDock;
    QPointer<GeoStationMapPointTool> mPickTool;
    GeoStationExtractionReview *mReview = nullptr;
    QPointer<GeoStationReviewTool> mReviewTool;
    QAction *mReviewAction = nullptr;
};

#endif // GEOSTATIONPLUGIN_H
