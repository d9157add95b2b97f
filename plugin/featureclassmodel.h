/***************************************************************************
  featureclassmodel.h - the table model of the feature classes
 ***************************************************************************/
#ifndef GEOSTATIONFEATURECLASSMODEL_H
#define GEOSTATIONFEATURECLASSMODEL_H

#include <QAbstractTableModel>
#include <QList>
#include <QString>
#include <QVariantMap>

#include "featureclass.h"

/**
 * The classes in a table: name, geometry, default attributes written as
 * "key=value; key=value". Editable; rows are added and removed by the dialog.
 */
class GeoStationFeatureClassModel : public QAbstractTableModel
{
    Q_OBJECT

  public:
    enum class Column
    {
      Name,
      Geometry,
      Attributes,
      Count
    };
    static constexpr int kColumnCount = static_cast<int>( Column::Count );

    explicit GeoStationFeatureClassModel( QObject *parent = nullptr );

    void setClasses( const QList<GeoStationFeatureClass> &classes );
    const QList<GeoStationFeatureClass> &classes() const { return mClasses; }

    //! Appends a class with a unique default name; returns its row.
    int addClass( GeoStationFeatureClass::Geometry geometry );
    void removeClassAt( int row );

    //! Checks the classes (as fromJson does); false with the reason.
    bool validate( QString *error ) const;

    static QString attributesText( const QVariantMap &attributes );
    static bool attributesFromText( const QString &text, QVariantMap &attributes, QString *error );

    int rowCount( const QModelIndex &parent = QModelIndex() ) const override;
    int columnCount( const QModelIndex &parent = QModelIndex() ) const override;
    QVariant data( const QModelIndex &index, int role = Qt::DisplayRole ) const override;
    bool setData( const QModelIndex &index, const QVariant &value, int role = Qt::EditRole ) override;
    QVariant headerData( int section, Qt::Orientation orientation, int role = Qt::DisplayRole ) const override;
    Qt::ItemFlags flags( const QModelIndex &index ) const override;

  private:
    QList<GeoStationFeatureClass> mClasses;
};

#endif // GEOSTATIONFEATURECLASSMODEL_H
