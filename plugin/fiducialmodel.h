/***************************************************************************
  fiducialmodel.h - the fiducials of a scanned photo as a table
  -------------------------------------------------------------------------
  One row per calibrated fiducial of the photo's camera: its photo
  coordinates (mm), where it was measured in the scan (detected or
  clicked), and its residual after the affine inner orientation (µm).
  Every change re-adjusts (core innerOrientation()) and emits
  innerOrientationChanged().
 ***************************************************************************/
#ifndef GEOSTATIONFIDUCIALMODEL_H
#define GEOSTATIONFIDUCIALMODEL_H

#include <map>
#include <optional>
#include <vector>

#include <QAbstractTableModel>
#include <QPointF>

#include "adjustment/innerorientation.h"
#include "camera/camera.h"

class GeoStationFiducialModel : public QAbstractTableModel
{
    Q_OBJECT

  public:
    enum class Column
    {
      Id,
      XMm,
      YMm,
      Col,
      Row,
      ResidualXUm,
      ResidualYUm,
      Count,
    };
    static constexpr int kColumnCount = static_cast<int>( Column::Count );

    explicit GeoStationFiducialModel( QObject *parent = nullptr );

    //! The camera's calibrated fiducials; clears the measurements.
    void setCamera( const geostation::Camera &camera );
    void setMeasurement( int row, const std::optional<QPointF> &pixelInScan );
    std::optional<QPointF> measurement( int row ) const;
    int rowOf( const QString &fiducialId ) const;
    const geostation::InnerOrientationSummary &summary() const { return mSummary; }
    //! Whether enough fiducials are measured for an inner orientation.
    bool oriented() const { return mSummary.ok(); }

    int rowCount( const QModelIndex &parent = QModelIndex() ) const override;
    int columnCount( const QModelIndex &parent = QModelIndex() ) const override;
    QVariant data( const QModelIndex &index, int role = Qt::DisplayRole ) const override;
    QVariant headerData( int section, Qt::Orientation orientation, int role = Qt::DisplayRole ) const override;

  signals:
    void innerOrientationChanged();

  private:
    void reorient();

    std::vector<geostation::Fiducial> mFiducials;
    std::map<std::string, QPointF> mMeasured;
    geostation::InnerOrientationSummary mSummary;
};

#endif // GEOSTATIONFIDUCIALMODEL_H
