/***************************************************************************
  featureclass.h - what the operator measures: named classes of features
  -------------------------------------------------------------------------
  A feature class has a name, a geometry (point, line or polygon) and
  default attributes written with every feature of the class. Classes are
  kept with the QGIS project as JSON; each class writes to its own layer of
  the measurement GeoPackage (CONVENTIONS §7), named after the class.
 ***************************************************************************/
#ifndef GEOSTATIONFEATURECLASS_H
#define GEOSTATIONFEATURECLASS_H

#include <QAbstractTableModel>
#include <QList>
#include <QString>
#include <QVariantMap>

struct GeoStationFeatureClass
{
  enum class Geometry
  {
    Point,
    Line,
    Polygon,
  };

  QString name;
  Geometry geometry = Geometry::Point;
  QVariantMap attributes; //!< default attribute values (text)

  //! "point", "line", "polygon"
  static QString geometryName( Geometry geometry );
  static bool geometryFromName( const QString &name, Geometry &geometry );

  //! The layer name in the GeoPackage: the name in lower case, other than letters, digits and _ replaced by _.
  QString layerName() const;

  //! Vertices needed to finish a feature.
  int minimumVertices() const { return geometry == Geometry::Point ? 1 : geometry == Geometry::Line ? 2 : 3; }

  bool operator==( const GeoStationFeatureClass &other ) const
  {
    return name == other.name && geometry == other.geometry && attributes == other.attributes;
  }

  //! The classes as JSON text (an array of {name, geometry, attributes}).
  static QString toJson( const QList<GeoStationFeatureClass> &classes );

  /**
   * Parses classes; on a problem returns false and says which entry and what
   * is wrong (missing name, unknown geometry, a name used twice, an attribute
   * that clashes with the measurement fields).
   */
  static bool fromJson( const QString &json, QList<GeoStationFeatureClass> &classes, QString *error );

  //! Names of the fields every measurement layer has (class, station, ...).
  static QStringList reservedFieldNames();
};

/**
 * The classes in a table: name, geometry, default attributes written as
 * "key=value; key=value". Editable; rows are added and removed by the dialog.
 */
class GeoStationFeatureClassModel : public QAbstractTableModel
{
    Q_OBJECT

  public:
    enum Column
    {
      Name,
      GeometryColumn,
      Attributes,
      ColumnCount
    };

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

#endif // GEOSTATIONFEATURECLASS_H
