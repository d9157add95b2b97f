/***************************************************************************
  multiviewsession.h - the state of the Multiview, kept with the project
  -------------------------------------------------------------------------
  The open block and its run of stations, the current station, which
  image each view shows, the feature classes, the measurement GeoPackage
  and the single-image settings (DEM layer, camera height above the road).
  No widgets: the dock, the Overview and the measurement follow its
  signals, and it is written to and read from the QGIS project.

  A view shows "camera c, k stations from the current one": stepping along
  the run keeps each view on its camera, so a pair formed across stations
  (this station's left image with the next station's) stays a pair.
 ***************************************************************************/
#ifndef GEOSTATIONMULTIVIEWSESSION_H
#define GEOSTATIONMULTIVIEWSESSION_H

#include <map>
#include <memory>

#include <QFileSystemWatcher>
#include <QObject>
#include <QStringList>
#include <QTimer>

#include <qgscoordinatereferencesystem.h>

#include "featureclass.h"
#include "geometry/projection.h"
#include "io/block.h"
#include "io/stationsequence.h"

class QgsProject;

class GeoStationMultiviewSession : public QObject
{
    Q_OBJECT

  public:
    static constexpr int sMaxViews = 6;

    struct ViewAssignment
    {
      QString cameraId;      //!< empty: the station's image at this view's position
      int stationOffset = 0; //!< stations from the current one
    };

    explicit GeoStationMultiviewSession( QObject *parent = nullptr );

    //! Loads a block; on failure returns false with one sentence and keeps the open block.
    bool openBlock( const QString &path, QString *error );
    /**
     * Reads the open block's file again, keeping the current station and
     * the views (done by itself, half a second after the file changes on
     * disk: a bundle adjustment or an import wrote it). Emits blockReloaded()
     * when its content changed, blockFileProblem() and keeps the loaded
     * block when it cannot be read now; false then.
     */
    bool reloadBlock();
    void closeBlock();
    bool hasBlock() const { return static_cast<bool>( mBlock ); }
    const geostation::Block *block() const { return mBlock.get(); }
    QString blockPath() const { return mBlockPath; }
    const geostation::StationSequence &run() const { return mRun; }
    //! The block CRS as QGIS reads it (invalid without a block).
    const QgsCoordinateReferenceSystem &crs() const { return mCrs; }

    int currentStation() const { return mCurrent; }
    QString currentStationId() const;
    //! Clamped to the run; emits stationChanged() when it changes.
    void setCurrentStation( int index );
    void stepStation( int step ) { setCurrentStation( mCurrent + step ); }

    int viewCount() const { return mViews.size(); }
    void setViewCount( int count );
    //! Shows an image in a view (any image of the block; the view keeps its camera and offset from then on).
    bool setViewImage( int view, const QString &imageId );
    //! The image id each view shows at the current station (empty: nothing).
    QStringList viewImages() const;
    const QList<ViewAssignment> &viewAssignments() const { return mViews; }

    //! The oriented image (camera, EO, scan affine) of an image, or nullptr if it is not oriented.
    const geostation::OrientedImage *orientedImage( const QString &imageId ) const;
    //! The station's time of an image ("" if none).
    QString imageTime( const QString &imageId ) const;
    //! The image's file, resolved against the block file ("" for an unknown image).
    QString imagePath( const QString &imageId ) const;
    QString imageStation( const QString &imageId ) const;

    const QList<GeoStationFeatureClass> &featureClasses() const { return mClasses; }
    void setFeatureClasses( const QList<GeoStationFeatureClass> &classes );
    QString currentClass() const { return mCurrentClass; }
    void setCurrentClass( const QString &name );
    const GeoStationFeatureClass *findClass( const QString &name ) const;

    QString targetGeoPackage() const { return mTarget; }
    void setTargetGeoPackage( const QString &path );
    //! The default target: measurements.gpkg beside the block file.
    QString defaultTargetGeoPackage() const;

    QString demLayerId() const { return mDemLayerId; }
    void setDemLayerId( const QString &layerId );
    double cameraHeightAboveRoadM() const { return mCameraHeight; }
    double roadPlaneSigmaM() const { return mRoadSigma; }
    void setRoadPlane( double cameraHeightAboveRoadM, double sigmaM );

    //! Writes the state into the project (scope "GeoStation").
    void writeToProject( QgsProject *project ) const;
    /**
     * Restores the state from a project. Returns false when the project has
     * no GeoStation state; on a block that cannot be opened, `error` says so
     * and the rest (classes, target) is still restored.
     */
    bool readFromProject( QgsProject *project, QString *error );

  signals:
    void blockChanged();
    //! The open block was read again from its changed file (reloadBlock()): one sentence on what changed.
    void blockReloaded( const QString &summary );
    //! The open block's file changed but cannot be read now (one sentence); the loaded block stays.
    void blockFileProblem( const QString &problem );
    void stationChanged( int index );
    void viewImagesChanged();
    void featureClassesChanged();
    void targetChanged();
    void settingsChanged();

  private:
    QString imageFor( const ViewAssignment &assignment, int viewIndex ) const;
    void resetViews();
    //! Watches the open block's file (and its folder: a file replaced by a rename drops a file watch).
    void watchBlockFile();
    //! The block file's size and time, to tell a real change from a touch of its folder.
    QString blockFileStamp() const;
    //! Makes the block the open one: its oriented images, CRS and run (the station and views are the caller's).
    void adoptBlock( std::unique_ptr<geostation::Block> block );
    //! The oriented images of a block (those that cannot be used for measuring are left out).
    static std::map<std::string, geostation::OrientedImage> orientedImages( const geostation::Block &block );

    std::unique_ptr<geostation::Block> mBlock;
    QString mBlockPath;
    QgsCoordinateReferenceSystem mCrs;
    geostation::StationSequence mRun;
    std::map<std::string, geostation::OrientedImage> mOriented;
    int mCurrent = -1;
    QList<ViewAssignment> mViews;
    QList<GeoStationFeatureClass> mClasses;
    QString mCurrentClass;
    QString mTarget;
    QString mDemLayerId;
    double mCameraHeight = 2.6;
    double mRoadSigma = 0.05;
    QFileSystemWatcher mWatcher;
    QTimer mReloadTimer;
    QString mLoadedStamp;
};

#endif // GEOSTATIONMULTIVIEWSESSION_H
