/***************************************************************************
  cameratablemodel.h - the cameras of a block as a table
  -------------------------------------------------------------------------
  Interior orientation per camera, in the block file's units: pixels, mm
  for the pixel size, lens coefficients as stored.
 ***************************************************************************/
#ifndef CAMERATABLEMODEL_H
#define CAMERATABLEMODEL_H

#include <QAbstractTableModel>

namespace geostation
{
  class Block;
}

class GeoStationCameraTableModel : public QAbstractTableModel
{
    Q_OBJECT

  public:
    enum class Column
    {
      Id,
      Size,
      F,
      Aspect,
      Cx,
      Cy,
      PixelSize,
      Model,
      K1,
      K2,
      P1,
      P2,
      K3,
      Images,
      Count,
    };
    static constexpr int kColumnCount = static_cast<int>( Column::Count );

    explicit GeoStationCameraTableModel( QObject *parent = nullptr );

    //! Shows the cameras of block (not owned; nullptr clears). Keep the block alive while shown.
    void setBlock( const geostation::Block *block );

    int rowCount( const QModelIndex &parent = QModelIndex() ) const override;
    int columnCount( const QModelIndex &parent = QModelIndex() ) const override;
    QVariant data( const QModelIndex &index, int role = Qt::DisplayRole ) const override;
    QVariant headerData( int section, Qt::Orientation orientation, int role = Qt::DisplayRole ) const override;

  private:
    const geostation::Block *mBlock = nullptr;
};

#endif // CAMERATABLEMODEL_H
