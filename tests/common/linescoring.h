// Road lines of the simulator's truth.gpkg and the buffer method for scoring
// traced or extracted lines against them:
//   completeness = truth length within the buffer of the result,
//   correctness  = result length within the buffer of the truth,
// measured in plan (XY), by sampling each polyline every few centimetres.
#ifndef GEOSTATION_TESTS_LINESCORING_H
#define GEOSTATION_TESTS_LINESCORING_H

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <gdal.h>
#include <ogr_api.h>

namespace geostation
{
  struct TruthRoadLine
  {
    std::string id, kind, marking;
    std::vector<Eigen::Vector3d> vertices;
  };

  //! The roads layer of a simulation's truth.gpkg.
  inline std::vector<TruthRoadLine> readTruthRoadLines( const std::filesystem::path &gpkg )
  {
    GDALAllRegister();
    GDALDatasetH ds = GDALOpenEx( gpkg.string().c_str(), GDAL_OF_VECTOR, nullptr, nullptr, nullptr );
    if ( !ds )
      throw std::runtime_error( "cannot open " + gpkg.string() );
    OGRLayerH layer = GDALDatasetGetLayerByName( ds, "roads" );
    if ( !layer )
    {
      GDALClose( ds );
      throw std::runtime_error( "no roads layer in " + gpkg.string() );
    }
    std::vector<TruthRoadLine> lines;
    while ( OGRFeatureH f = OGR_L_GetNextFeature( layer ) )
    {
      TruthRoadLine line;
      line.id = OGR_F_GetFieldAsString( f, OGR_F_GetFieldIndex( f, "id" ) );
      line.kind = OGR_F_GetFieldAsString( f, OGR_F_GetFieldIndex( f, "kind" ) );
      line.marking = OGR_F_GetFieldAsString( f, OGR_F_GetFieldIndex( f, "marking" ) );
      OGRGeometryH g = OGR_F_GetGeometryRef( f );
      for ( int i = 0; i < OGR_G_GetPointCount( g ); ++i )
        line.vertices.emplace_back( OGR_G_GetX( g, i ), OGR_G_GetY( g, i ), OGR_G_GetZ( g, i ) );
      lines.push_back( line );
      OGR_F_Destroy( f );
    }
    GDALClose( ds );
    return lines;
  }

  /**
   * The truth line whose id starts with `prefix` (e.g. "R1-edge-right" or
   * "R1-separator2"), its parts joined in order: a dashed marking becomes
   * the continuous line through its dashes, as a surveyor traces it.
   */
  inline std::vector<Eigen::Vector3d> joinedTruthLine( const std::vector<TruthRoadLine> &lines, const std::string &prefix )
  {
    std::vector<Eigen::Vector3d> out;
    for ( const TruthRoadLine &l : lines )
      if ( l.id.rfind( prefix + "-", 0 ) == 0 )
        out.insert( out.end(), l.vertices.begin(), l.vertices.end() );
    return out;
  }

  struct PolylineProjection
  {
    double distance = std::numeric_limits<double>::infinity();
    double station = 0.0; //!< along the polyline
    Eigen::Vector3d point = Eigen::Vector3d::Zero();
    Eigen::Vector3d tangent = Eigen::Vector3d::UnitX();
  };

  //! Nearest point of a polyline, in plan (xyOnly) or in 3-D.
  inline PolylineProjection projectOnto( const std::vector<Eigen::Vector3d> &line, const Eigen::Vector3d &p, bool xyOnly )
  {
    PolylineProjection best;
    double station = 0.0;
    for ( size_t i = 0; i + 1 < line.size(); ++i )
    {
      Eigen::Vector3d a = line[i], b = line[i + 1], q = p;
      if ( xyOnly )
      {
        a.z() = b.z() = q.z() = 0.0;
      }
      const Eigen::Vector3d ab = b - a;
      const double len = ab.norm();
      const double t = len > 0 ? std::clamp( ( q - a ).dot( ab ) / ( len * len ), 0.0, 1.0 ) : 0.0;
      const double d = ( a + t * ab - q ).norm();
      if ( d < best.distance )
      {
        best.distance = d;
        best.station = station + t * len;
        best.point = line[i] + t * ( line[i + 1] - line[i] );
        best.tangent = len > 0 ? Eigen::Vector3d( ( line[i + 1] - line[i] ).normalized() ) : Eigen::Vector3d::UnitX();
      }
      station += len;
    }
    return best;
  }

  //! The part of a polyline between two stations (metres along it).
  inline std::vector<Eigen::Vector3d> polylineBetween( const std::vector<Eigen::Vector3d> &line, double from, double to )
  {
    std::vector<Eigen::Vector3d> out;
    double station = 0.0;
    for ( size_t i = 0; i + 1 < line.size(); ++i )
    {
      const double len = ( line[i + 1] - line[i] ).norm();
      for ( const double s : { from, to } )
        if ( s >= station && s <= station + len && len > 0 && ( out.empty() || s == to ) )
          out.push_back( line[i] + ( s - station ) / len * ( line[i + 1] - line[i] ) );
      if ( station + len > from && station + len < to )
        out.push_back( line[i + 1] );
      station += len;
    }
    std::stable_sort( out.begin(), out.end(), [&]( const Eigen::Vector3d &a, const Eigen::Vector3d &b ) { return projectOnto( line, a, false ).station < projectOnto( line, b, false ).station; } );
    return out;
  }

  inline double polylineLength( const std::vector<Eigen::Vector3d> &line )
  {
    double s = 0.0;
    for ( size_t i = 0; i + 1 < line.size(); ++i )
      s += ( line[i + 1] - line[i] ).head<2>().norm();
    return s;
  }

  //! Length of `line` (in plan) within `buffer` of `reference`, sampled every `step` metres.
  inline double lengthWithinBuffer( const std::vector<Eigen::Vector3d> &line, const std::vector<Eigen::Vector3d> &reference, double buffer, double step = 0.02 )
  {
    double inside = 0.0;
    for ( size_t i = 0; i + 1 < line.size(); ++i )
    {
      const double len = ( line[i + 1] - line[i] ).head<2>().norm();
      const int n = std::max( 1, static_cast<int>( std::ceil( len / step ) ) );
      for ( int k = 0; k < n; ++k )
      {
        const Eigen::Vector3d p = line[i] + ( k + 0.5 ) / n * ( line[i + 1] - line[i] );
        if ( projectOnto( reference, p, true ).distance <= buffer )
          inside += len / n;
      }
    }
    return inside;
  }

  /**
   * The share of the lines' length lying within `tolerance` of another of them and about parallel (within
   * `parallelDeg`): a road found twice, which the buffer scores do not see. Within `nodeLength` of a line's
   * ends it is a node (a junction, a line continued), not a repeat: left out on both sides. Units as the lines'.
   */
  inline double doubledShare( const std::vector<std::vector<Eigen::Vector3d>> &lines, double tolerance, double nodeLength, double parallelDeg = 30.0, double step = 0.5 )
  {
    std::vector<std::vector<Eigen::Vector3d>> inner;
    double total = 0.0, doubled = 0.0;
    for ( const auto &l : lines )
    {
      const double len = polylineLength( l );
      total += len;
      inner.push_back( len > 2 * nodeLength ? polylineBetween( l, nodeLength, len - nodeLength ) : std::vector<Eigen::Vector3d>() );
    }
    const double minCos = std::cos( parallelDeg * 3.14159265358979323846 / 180.0 );
    for ( size_t i = 0; i < inner.size(); ++i )
      for ( size_t k = 0; k + 1 < inner[i].size(); ++k )
      {
        const Eigen::Vector3d a = inner[i][k], b = inner[i][k + 1];
        const double len = ( b - a ).head<2>().norm();
        if ( !( len > 0 ) )
          continue;
        const Eigen::Vector3d dir = ( b - a ).normalized();
        const int n = std::max( 1, static_cast<int>( std::ceil( len / step ) ) );
        for ( int m = 0; m < n; ++m )
        {
          const Eigen::Vector3d p = a + ( m + 0.5 ) / n * ( b - a );
          for ( size_t j = 0; j < inner.size(); ++j )
          {
            if ( j == i || inner[j].size() < 2 )
              continue;
            const PolylineProjection q = projectOnto( inner[j], p, true );
            if ( q.distance <= tolerance && std::abs( q.tangent.head<2>().dot( dir.head<2>() ) ) >= minCos )
            {
              doubled += len / n;
              break;
            }
          }
        }
      }
    return total > 0 ? doubled / total : 0.0;
  }

  struct BufferScore
  {
    double completeness = 0.0, correctness = 0.0;
  };

  //! The buffer method's quality (Wiedemann): matched / (matched + missed + false) = 1 / (1/completeness + 1/correctness - 1).
  inline double quality( const BufferScore &s )
  {
    if ( !( s.completeness > 0.0 ) || !( s.correctness > 0.0 ) )
      return 0.0;
    return 1.0 / ( 1.0 / s.completeness + 1.0 / s.correctness - 1.0 );
  }

  inline BufferScore bufferScore( const std::vector<Eigen::Vector3d> &result, const std::vector<Eigen::Vector3d> &truth, double buffer )
  {
    BufferScore s;
    const double truthLength = polylineLength( truth ), resultLength = polylineLength( result );
    s.completeness = truthLength > 0 ? lengthWithinBuffer( truth, result, buffer ) / truthLength : 0.0;
    s.correctness = resultLength > 0 ? lengthWithinBuffer( result, truth, buffer ) / resultLength : 0.0;
    return s;
  }
}

#endif // GEOSTATION_TESTS_LINESCORING_H
