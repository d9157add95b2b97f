/***************************************************************************
  camerapanel.h - the Multiview's Cameras panel
  -------------------------------------------------------------------------
  Interior and exterior orientation of the images the views show: camera,
  f, cx, cy and lens model; projection centre, omega / phi / kappa, and the
  GNSS/INS sigmas where the block has them. Read-only.
 ***************************************************************************/
#ifndef GEOSTATIONCAMERAPANEL_H
#define GEOSTATIONCAMERAPANEL_H

#include <QTableWidget>

namespace geostation
{
  class Block;
}

class GeoStationCameraPanel : public QTableWidget
{
    Q_OBJECT

  public:
    explicit GeoStationCameraPanel( QWidget *parent = nullptr );

    //! One row per image id of the block (unknown ids are left out); empty without a block.
    void showImages( const geostation::Block *block, const QStringList &ids );
};

#endif // GEOSTATIONCAMERAPANEL_H
