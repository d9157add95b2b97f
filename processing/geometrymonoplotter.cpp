/***************************************************************************
  geometrymonoplotter.cpp - an image-space geometry onto the DEM, for monoplot
 ***************************************************************************/
#include "geometrymonoplotter.h"

#include <tuple>

#include <QObject>

#include "dem/demintersection.h"
#include "geometry/imagespace.h"
#include "geometrymapper.h"

namespace GeoStationProcessing
{
  void GeometryMonoplotter::reset( const QString &why, const QString &statusName )
  {
    worst.setZero();
    vertices = 0;
    bridged = 0;
    cutVertices = 0;
    fail( why, statusName );
  }

  void GeometryMonoplotter::fail( const QString &why, const QString &statusName )
  {
    problem = why;
    status = statusName;
  }

  bool GeometryMonoplotter::inFrame( const QgsPoint &p ) const
  {
    const Eigen::Vector2d pixel = geostation::pixelOfImageSpace( Eigen::Vector2d( p.x(), p.y() ) );
    return pixel.x() >= 0.0 && pixel.x() <= width && pixel.y() >= 0.0 && pixel.y() <= height;
  }

  std::optional<QgsPoint> GeometryMonoplotter::point( const Eigen::Vector2d &pixel )
  {
    const geostation::MonoplotPoint g = monoplotter.imageToGround( pixel );
    if ( !g.ok() )
    {
      fail( QObject::tr( "pixel (%1, %2): %3" ).arg( pixel.x(), 0, 'f', 1 ).arg( pixel.y(), 0, 'f', 1 ).arg( QString::fromStdString( g.message ) ),
            QString::fromStdString( geostation::demIntersectionStatusName( g.status ) ) );
      return std::nullopt;
    }
    worst = worst.cwiseMax( g.sigmaM );
    ++vertices;
    bridged += g.onBridgedCells() ? 1 : 0;
    return QgsPoint( g.world.x(), g.world.y(), g.world.z() );
  }

  std::unique_ptr<QgsLineString> GeometryMonoplotter::line( const QgsLineString &in, bool closed )
  {
    std::vector<Eigen::Vector2d> pixels;
    for ( int i = 0; i < in.numPoints(); ++i )
    {
      if ( !inFrame( in.pointN( i ) ) )
      {
        fail( QObject::tr( "vertex (%1, %2) lies outside the image frame" ).arg( in.xAt( i ) ).arg( in.yAt( i ) ), QStringLiteral( "outside_image" ) );
        return nullptr;
      }
      pixels.emplace_back( in.xAt( i ), -in.yAt( i ) );
    }
    const std::vector<geostation::MonoplotPoint> ground = monoplotter.imageLineToGround( pixels, densifyPx );
    size_t first = 0, last = ground.empty() ? 0 : ground.size() - 1;
    for ( const geostation::MonoplotPoint &g : ground )
      if ( !g.ok() )
      {
        fail( QObject::tr( "pixel (%1, %2): %3" ).arg( g.pixelInImage.x(), 0, 'f', 1 ).arg( g.pixelInImage.y(), 0, 'f', 1 ).arg( QString::fromStdString( g.message ) ),
              QString::fromStdString( geostation::demIntersectionStatusName( g.status ) ) );
        // a ring cannot be cut; a line keeps its longest resolved part
        const std::vector<std::pair<size_t, size_t>> runs = geostation::resolvedRuns( ground );
        if ( closed || runs.empty() )
          return nullptr;
        std::tie( first, last ) = runs.front();
        cutVertices += static_cast<int>( ground.size() - ( last - first + 1 ) );
        break;
      }
    QVector<QgsPoint> out;
    for ( size_t k = first; k <= last && k < ground.size(); ++k )
    {
      const geostation::MonoplotPoint &g = ground[k];
      worst = worst.cwiseMax( g.sigmaM );
      ++vertices;
      bridged += g.onBridgedCells() ? 1 : 0;
      out << QgsPoint( g.world.x(), g.world.y(), g.world.z() );
    }
    if ( closed && !out.isEmpty() )
      out.last() = out.first(); // the ring closes exactly
    return std::make_unique<QgsLineString>( out );
  }

  std::unique_ptr<QgsAbstractGeometry> GeometryMonoplotter::geometry( const QgsAbstractGeometry *g )
  {
    GeoStationProcessing::GeometryMapper mapper;
    mapper.point = [this]( const QgsPoint & p ) -> std::optional<QgsPoint>
    {
      if ( !inFrame( p ) )
      {
        fail( QObject::tr( "point (%1, %2) lies outside the image frame" ).arg( p.x() ).arg( p.y() ), QStringLiteral( "outside_image" ) );
        return std::nullopt;
      }
      return point( geostation::pixelOfImageSpace( Eigen::Vector2d( p.x(), p.y() ) ) );
    };
    mapper.line = [this]( const QgsLineString & l, bool closed ) { return line( l, closed ); };
    mapper.collectionType = []( QgsWkbTypes::Type type ) { return QgsWkbTypes::addZ( type ); }; // map features get heights
    return GeoStationProcessing::mapGeometry( g, mapper );
  }

} // namespace GeoStationProcessing
