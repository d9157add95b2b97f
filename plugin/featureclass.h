/***************************************************************************
  featureclass.h - what the operator measures: named classes of features
  -------------------------------------------------------------------------
  A feature class has a name, a geometry (point, line or polygon) and
  default attributes written with every feature of the class. Classes are
  kept with the QGIS project as JSON; each class writes to its own layer of
  the measurement GeoPackage (docs/conventions.md §7), named after the class.
 ***************************************************************************/
#ifndef GEOSTATIONFEATURECLASS_H
#define GEOSTATIONFEATURECLASS_H

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

#endif // GEOSTATIONFEATURECLASS_H
