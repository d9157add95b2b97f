/***************************************************************************
  addphotodialog.h - GeoStation > Add Photo...: a photo and its camera
  -------------------------------------------------------------------------
  The photo file, the camera (one of the open block's of the photo's
  size, or a new one, prefilled from the file's EXIF or a normal-lens
  default; a film camera with its pixel size and calibrated fiducials),
  and, when no block is open, the new block's file and CRS. Only collects
  and validates; core adds the photo (photoimport.h).
 ***************************************************************************/
#ifndef GEOSTATIONADDPHOTODIALOG_H
#define GEOSTATIONADDPHOTODIALOG_H

#include <QDialog>

#include <qgscoordinatereferencesystem.h>

#include "camera/camera.h"
#include "ui_geostationaddphotodialogbase.h"

class GeoStationMultiviewSession;

namespace geostation
{
  class Block;
}

class GeoStationAddPhotoDialog : public QDialog, private Ui::GeoStationAddPhotoDialogBase
{
    Q_OBJECT

  public:
    //! `block` is the open block (nullptr: a new block is made; the dialog then asks for its file and CRS).
    GeoStationAddPhotoDialog( const geostation::Block *block, const QgsCoordinateReferenceSystem &defaultCrs, QWidget *parent = nullptr );

    QString photoPath() const;
    void setPhotoPath( const QString &path );
    QString newBlockPath() const;
    QgsCoordinateReferenceSystem crs() const;
    /**
     * The camera chosen, or the new one as described (validated as the
     * block reader does). False with one sentence when it is not valid.
     */
    bool camera( geostation::Camera *camera, QString *error ) const;
    //! The problem shown (empty when none).
    QString problem() const;

    /**
     * Adds the photo to the session's open block, or to a new block saved
     * to `newBlockPath` in `crs` and opened; the block file is written
     * atomically. Returns the new image's id, or an empty string with one
     * sentence in `error` (the open block and its file are then unchanged).
     */
    /**
     * The camera for a photo added without the dialog: `cameraJson` as in
     * the block file, or, when empty, the block's camera of the photo's
     * size, else one from the file's EXIF. False with one sentence.
     */
    static bool cameraForPhoto( const geostation::Block *block, const QString &photoPath, const QString &cameraJson, geostation::Camera *camera, QString *error );

    static QString addToBlock( GeoStationMultiviewSession *session, const QString &photoPath, const geostation::Camera &camera, const QString &newBlockPath,
                               const QgsCoordinateReferenceSystem &crs, QString *error );

  public slots:
    void accept() override;

  private slots:
    void photoChanged();
    void cameraChoiceChanged();

  private:
    const geostation::Block *mBlock;
    int mPhotoWidth = 0, mPhotoHeight = 0;
};

#endif // GEOSTATIONADDPHOTODIALOG_H
