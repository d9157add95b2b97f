/***************************************************************************
  changeinimages.cpp - a reviewed map change shown in the Multiview
 ***************************************************************************/
#include "changeinimages.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <qgscoordinatetransform.h>
#include <qgsexception.h>
#include <qgsproject.h>

std::vector<Eigen::Vector3d> courseInBlockCrs( const QgsGeometry &course, const QgsCoordinateReferenceSystem &courseCrs,
    const QgsCoordinateReferenceSystem &blockCrs, double heightWhereNone )
{
  if ( course.isNull() || course.isEmpty() )
    return {};
  QgsGeometry g = course;
  if ( courseCrs.isValid() && blockCrs.isValid() && courseCrs != blockCrs )
  {
    try
    {
      g.transform( QgsCoordinateTransform( courseCrs, blockCrs, QgsProject::instance()->transformContext() ) );
    }
    catch ( const QgsCsException & )
    {
      return {};
    }
  }
  const bool hasZ = QgsWkbTypes::hasZ( g.wkbType() );
  std::vector<Eigen::Vector3d> out;
  for ( auto v = g.vertices_begin(); v != g.vertices_end(); ++v )
    out.emplace_back( ( *v ).x(), ( *v ).y(), hasZ && std::isfinite( ( *v ).z() ) ? ( *v ).z() : heightWhereNone );
  return out;
}

std::optional<double> meanHeight( const std::vector<Eigen::Vector3d> &course )
{
  double sum = 0.0;
  int n = 0;
  for ( const Eigen::Vector3d &p : course )
    if ( std::isfinite( p.z() ) )
    {
      sum += p.z();
      ++n;
    }
  return n > 0 ? std::optional<double>( sum / n ) : std::nullopt;
}

QStringList imagesSeeing( const Eigen::Vector3d &point, const QStringList &imageIds,
                          const std::function<const geostation::OrientedImage *( const QString & )> &oriented )
{
  std::vector<std::pair<double, QString>> seeing;
  for ( const QString &id : imageIds )
  {
    const geostation::OrientedImage *image = oriented( id );
    if ( !image )
      continue;
    const geostation::GroundProjection p = image->projectGroundToPixel( point );
    if ( !p.ok() || !p.inFrame )
      continue;
    const Eigen::Vector2d centre( image->camera().width / 2.0, image->camera().height / 2.0 );
    seeing.emplace_back( ( p.pixelInImage - centre ).norm() / centre.norm(), id );
  }
  std::stable_sort( seeing.begin(), seeing.end(), []( const auto &a, const auto &b ) { return a.first < b.first; } );
  QStringList ids;
  for ( const auto &s : seeing )
    ids << s.second;
  return ids;
}
