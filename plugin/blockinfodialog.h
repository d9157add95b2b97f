/***************************************************************************
  blockinfodialog.h - what an opened block contains
 ***************************************************************************/
#ifndef BLOCKINFODIALOG_H
#define BLOCKINFODIALOG_H

#include <QDialog>

#include "ui_geostationblockinfodialogbase.h"

namespace geostation
{
  class Block;
}
class GeoStationCameraTableModel;

class GeoStationBlockInfoDialog : public QDialog, private Ui::GeoStationBlockInfoDialogBase
{
    Q_OBJECT

  public:
    //! Shows block, which must outlive the dialog.
    GeoStationBlockInfoDialog( const geostation::Block &block, QWidget *parent = nullptr );

    //! One line: cameras, stations, images, oriented images.
    static QString contentsSummary( const geostation::Block &block );

  private:
    GeoStationCameraTableModel *mCameraModel = nullptr;
};

#endif // BLOCKINFODIALOG_H
