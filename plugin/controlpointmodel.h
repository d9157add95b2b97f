/***************************************************************************
  controlpointmodel.h - the orientation dock's control-point table
  -------------------------------------------------------------------------
  One row per control point of the photo being oriented, as the
  georeferencer's QgsGCPListModel: the point's id, whether it is used, a
  check point or off, its pixel in the photo's file, its ground position
  (block CRS, metres), and what the current orientation says of it -
  residual in pixels, error on the ground, Baarda's w - plus the
  semi-automatic mode's offer when there is one. Every change re-adjusts
  (core orientPhoto()) and emits orientationChanged(); the maths is core's.
 ***************************************************************************/
#ifndef GEOSTATIONCONTROLPOINTMODEL_H
#define GEOSTATIONCONTROLPOINTMODEL_H

#include <map>
#include <optional>
#include <vector>

#include <QAbstractTableModel>
#include <QPointF>

#include "workstation/photoorientation.h"

class GeoStationControlPointModel : public QAbstractTableModel
{
    Q_OBJECT

  public:
    enum class Column
    {
      Id,
      Use,     //!< checkable: in the adjustment or not
      Check,   //!< checkable: a check point
      Col,
      Row,
      X,
      Y,
      Z,
      ResidualCol,
      ResidualRow,
      ResidualPx,
      GroundErrorM,
      W,
      Status,
      Count,
    };
    static constexpr int kColumnCount = static_cast<int>( Column::Count );

    explicit GeoStationControlPointModel( QObject *parent = nullptr );

    /**
     * The photo's camera and, for scanned film, its scan affine; clears the
     * orientation (the points stay). Call before adding points.
     */
    void setCamera( const geostation::Camera &camera, const std::optional<Eigen::Matrix<double, 2, 3>> &nominalFromFile );
    const geostation::Camera &camera() const { return mCamera; }
    const std::optional<Eigen::Matrix<double, 2, 3>> &nominalFromFile() const { return mNominalFromFile; }

    //! Camera parameters freed in the adjustment.
    void setOptions( const geostation::PhotoOrientationOptions &options );
    const geostation::PhotoOrientationOptions &options() const { return mOptions; }

    /**
     * Adds a point or, for an id already listed, sets its ground position
     * (a control layer read again keeps what was measured in the photo).
     * Returns its row.
     */
    int setGroundPoint( const QString &id, const Eigen::Vector3d &worldM );
    //! A new point with a free id ("P1", "P2", ...) and no ground position yet; its row.
    int addPoint();
    bool removePoint( int row );
    //! The pixel measured in the photo's file; nothing clears it.
    void setPixel( int row, const std::optional<QPointF> &pixelInFile );
    void setRole( int row, geostation::ControlRole role );
    void clear();

    const std::vector<geostation::PhotoControlPoint> &points() const { return mPoints; }
    const geostation::PhotoOrientationSummary &summary() const { return mSummary; }
    int rowOf( const QString &id ) const;
    //! Whether the row has a ground position (a point added by addPoint() has none until given one).
    bool hasGround( int row ) const;

    // ---- the semi-automatic mode ----
    //! Offers for rows not measured (replacing earlier ones); shown in the Status column.
    void setOffers( const std::vector<geostation::ControlOffer> &offers );
    const std::map<std::string, geostation::ControlOffer> &offers() const { return mOffers; }
    //! Accepts every offer found, and the flagged offers of `rows` (the operator looked at them); returns how many were taken.
    int acceptOffers( const QList<int> &rows = QList<int>() );
    void rejectOffers();

    int rowCount( const QModelIndex &parent = QModelIndex() ) const override;
    int columnCount( const QModelIndex &parent = QModelIndex() ) const override;
    QVariant data( const QModelIndex &index, int role = Qt::DisplayRole ) const override;
    bool setData( const QModelIndex &index, const QVariant &value, int role = Qt::EditRole ) override;
    Qt::ItemFlags flags( const QModelIndex &index ) const override;
    QVariant headerData( int section, Qt::Orientation orientation, int role = Qt::DisplayRole ) const override;

  signals:
    //! After every re-adjustment: the summary's message is one sentence for the dock.
    void orientationChanged();

  private:
    void reorient();
    QString statusText( int row ) const;

    geostation::Camera mCamera;
    std::optional<Eigen::Matrix<double, 2, 3>> mNominalFromFile;
    geostation::PhotoOrientationOptions mOptions;
    std::vector<geostation::PhotoControlPoint> mPoints;
    std::vector<bool> mHasGround;
    geostation::PhotoOrientationSummary mSummary;
    std::map<std::string, geostation::ControlOffer> mOffers;
};

#endif // GEOSTATIONCONTROLPOINTMODEL_H
