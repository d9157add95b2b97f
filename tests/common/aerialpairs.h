// Simulated aerial stereo pairs for the road-extraction tests, and their
// scoring against the simulator's truth in image space (buffer method).
// Each pair is simulated once per test process.
#ifndef GEOSTATION_TESTS_AERIALPAIRS_H
#define GEOSTATION_TESTS_AERIALPAIRS_H

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>
#include <tuple>
#include <unistd.h>
#include <vector>

#include <Eigen/Core>
#include <gdal.h>
#include <ogr_api.h>
#include <ogr_srs_api.h>
#include <opencv2/imgproc.hpp>

#include "extraction/lineextractor.h"
#include "extraction/resultmatrix.h"
#include "io/block.h"
#include "io/rasterfile.h"
#include "linescoring.h"
#include "simulation/surveysimulator.h"

namespace geostation::testing
{
  struct AerialPair
  {
    std::filesystem::path dir;
    Block block, truth;
    std::vector<TruthRoadLine> roads;
    cv::Mat left, right; //!< luminance
  };

  inline cv::Mat luminance( const std::filesystem::path &file )
  {
    const RasterImage raster = readRaster( file.string() );
    cv::Mat grey;
    if ( raster.pixels.channels() == 3 )
      cv::cvtColor( raster.pixels, grey, cv::COLOR_RGB2GRAY );
    else
      grey = raster.pixels;
    return grey;
  }

  inline AerialPair simulatePair( const std::string &name, const std::string &roadsPath, uint32_t seed )
  {
    AerialPair p;
    p.dir = std::filesystem::temp_directory_path() / ( "geostation-extraction-" + std::to_string( ::getpid() ) ) / name;
    SimulationOptions o;
    o.preset = SurveyPreset::AerialStereo;
    o.outputDir = p.dir;
    o.stations = 2;
    o.groundPixelSizeM = 0.5;
    o.seed = seed;
    o.roadsPath = roadsPath;
    o.degradation.noiseSigma = 4.0;
    simulateSurvey( o );
    p.block = Block::load( p.dir / "block.geostation.json" );
    p.truth = Block::load( p.dir / "truth.geostation.json" );
    p.roads = readTruthRoadLines( p.dir / "truth.gpkg" );
    p.left = luminance( p.block.imageFilePath( p.block.images.at( 0 ) ) );
    p.right = luminance( p.block.imageFilePath( p.block.images.at( 1 ) ) );
    return p;
  }

  inline void removeTemporaries()
  {
    std::error_code ec;
    std::filesystem::remove_all( std::filesystem::temp_directory_path() / ( "geostation-extraction-" + std::to_string( ::getpid() ) ), ec );
  }

  //! The preset's layout with other terrain, trees, shadows, cars and noise: simulated once per process and seed.
  inline const AerialPair &seedPair( uint32_t seed )
  {
    static std::map<uint32_t, AerialPair> pairs;
    const auto found = pairs.find( seed );
    if ( found != pairs.end() )
      return found->second;
    std::atexit( removeTemporaries );
    return pairs.emplace( seed, simulatePair( "seed" + std::to_string( seed ), "", seed ) ).first->second;
  }

  //! The aerial_stereo preset's roads: a curved main road, a side road and a third road, two T junctions.
  inline const AerialPair &aerialPair()
  {
    static const AerialPair pair = []
    {
      std::atexit( removeTemporaries );
      return simulatePair( "preset", "", 3 );
    }();
    return pair;
  }

  /**
   * A network laid out differently, from a road layer: a dual carriageway
   * (2 lanes each way, 14 m) crossed by two 7 m roads, one of them bending,
   * and a third 7 m road meeting the straight one in a T.
   */
  inline const AerialPair &townPair()
  {
    static const AerialPair pair = []
    {
      std::atexit( removeTemporaries );
      const std::filesystem::path dir = std::filesystem::temp_directory_path() / ( "geostation-extraction-" + std::to_string( ::getpid() ) );
      std::filesystem::create_directories( dir );
      const std::string path = ( dir / "town.gpkg" ).string();
      GDALAllRegister();
      GDALDriverH driver = GDALGetDriverByName( "GPKG" );
      GDALDatasetH ds = GDALCreate( driver, path.c_str(), 0, 0, 0, GDT_Unknown, nullptr );
      OGRSpatialReferenceH srs = OSRNewSpatialReference( nullptr );
      OSRImportFromEPSG( srs, 32617 );
      OGRLayerH layer = GDALDatasetCreateLayer( ds, "roads", srs, wkbLineString, nullptr );
      OSRDestroySpatialReference( srs );
      OGRFieldDefnH id = OGR_Fld_Create( "id", OFTString ), lanes = OGR_Fld_Create( "lanes", OFTInteger );
      OGR_L_CreateField( layer, id, TRUE );
      OGR_L_CreateField( layer, lanes, TRUE );
      OGR_Fld_Destroy( id );
      OGR_Fld_Destroy( lanes );
      const double x0 = 500000.0, y0 = 4400000.0;
      const std::vector<std::tuple<std::string, int, std::vector<Eigen::Vector2d>>> roads {
        { "D1", 2, { { -400, 10 }, { 400, -10 } } },
        { "C1", 1, { { -20, -400 }, { 10, 400 } } },
        { "C2", 1, { { 150, -400 }, { 140, -120 }, { 110, 60 }, { 60, 220 }, { 20, 400 } } },
        { "T1", 1, { { -300, 150 }, { -120, 140 }, { 0.6, 150 } } },
      };
      for ( const auto &[name, lanesPerDirection, vertices] : roads )
      {
        OGRFeatureH f = OGR_F_Create( OGR_L_GetLayerDefn( layer ) );
        OGR_F_SetFieldString( f, 0, name.c_str() );
        OGR_F_SetFieldInteger( f, 1, lanesPerDirection );
        OGRGeometryH g = OGR_G_CreateGeometry( wkbLineString );
        for ( const Eigen::Vector2d &v : vertices )
          OGR_G_AddPoint_2D( g, x0 + v.x(), y0 + v.y() );
        OGR_F_SetGeometryDirectly( f, g );
        if ( OGR_L_CreateFeature( layer, f ) != OGRERR_NONE )
          throw std::runtime_error( "cannot write the road layer " + path );
        OGR_F_Destroy( f );
      }
      GDALClose( ds );
      return simulatePair( "town", path, 11 );
    }();
    return pair;
  }

  //! Appends `point` to the current run while `keep` holds; otherwise the run (if a line) joins `runs` and a new one starts.
  inline void extendRun( std::vector<std::vector<Eigen::Vector3d>> &runs, std::vector<Eigen::Vector3d> &run, bool keep, const Eigen::Vector3d &point )
  {
    if ( keep )
    {
      run.push_back( point );
      return;
    }
    if ( run.size() > 1 )
      runs.push_back( run );
    run.clear();
  }

  /**
   * The truth centre lines projected into an image (x = col, y = row, z = 0),
   * densified to 1 m, clipped to the frame (with `stereo`: to the part seen by
   * both images, 10 px inside their frames).
   */
  inline std::vector<std::vector<Eigen::Vector3d>> truthCentreLinesInImage( const AerialPair &pair, int imageIndex, bool stereo = false )
  {
    const OrientedImage image = pair.truth.orientedImage( pair.truth.images.at( imageIndex ) );
    const OrientedImage other = pair.truth.orientedImage( pair.truth.images.at( 1 - imageIndex ) );
    const auto inside = []( const GroundProjection &g, const OrientedImage &i )
    {
      return g.ok() && g.pixelInImage.x() > 10 && g.pixelInImage.y() > 10 && g.pixelInImage.x() < i.camera().width - 10 && g.pixelInImage.y() < i.camera().height - 10;
    };
    std::vector<std::vector<Eigen::Vector3d>> out;
    for ( const TruthRoadLine &line : pair.roads )
    {
      if ( line.kind != "centre" )
        continue;
      std::vector<Eigen::Vector3d> run;
      for ( size_t i = 0; i + 1 < line.vertices.size(); ++i )
      {
        const Eigen::Vector3d a = line.vertices[i], b = line.vertices[i + 1];
        const int n = std::max( 1, static_cast<int>( std::ceil( ( b - a ).norm() ) ) );
        for ( int k = 0; k < n; ++k )
        {
          const Eigen::Vector3d ground = a + ( b - a ) * ( static_cast<double>( k ) / n );
          const GroundProjection g = image.projectGroundToPixel( ground );
          const bool seen = g.ok() && g.inFrame && ( !stereo || ( inside( g, image ) && inside( other.projectGroundToPixel( ground ), other ) ) );
          extendRun( out, run, seen, Eigen::Vector3d( g.pixelInImage.x(), g.pixelInImage.y(), 0.0 ) );
        }
      }
      if ( run.size() > 1 )
        out.push_back( run );
    }
    return out;
  }

  //! Buffer scores of image-space polylines against image-space truth (pixels).
  inline BufferScore scoreInImage( const std::vector<std::vector<Eigen::Vector3d>> &result, const std::vector<std::vector<Eigen::Vector3d>> &truth, double bufferPx )
  {
    double truthLength = 0, truthInside = 0, resultLength = 0, resultInside = 0;
    for ( const auto &t : truth )
    {
      truthLength += polylineLength( t );
      double best = 0;
      // within the buffer of any result line (sampled per sample point: take the union by testing each sample against all lines)
      for ( size_t i = 0; i + 1 < t.size(); ++i )
      {
        const double len = ( t[i + 1] - t[i] ).head<2>().norm();
        const Eigen::Vector3d mid = 0.5 * ( t[i] + t[i + 1] );
        for ( const auto &r : result )
          if ( projectOnto( r, mid, true ).distance <= bufferPx )
          {
            best += len;
            break;
          }
      }
      truthInside += best;
    }
    for ( const auto &r : result )
    {
      resultLength += polylineLength( r );
      for ( size_t i = 0; i + 1 < r.size(); ++i )
      {
        const double len = ( r[i + 1] - r[i] ).head<2>().norm();
        const int n = std::max( 1, static_cast<int>( std::ceil( len ) ) );
        for ( int k = 0; k < n; ++k )
        {
          const Eigen::Vector3d p = r[i] + ( k + 0.5 ) / n * ( r[i + 1] - r[i] );
          for ( const auto &t : truth )
            if ( projectOnto( t, p, true ).distance <= bufferPx )
            {
              resultInside += len / n;
              break;
            }
        }
      }
    }
    BufferScore s;
    s.completeness = truthLength > 0 ? truthInside / truthLength : 0;
    s.correctness = resultLength > 0 ? resultInside / resultLength : 0;
    return s;
  }

  inline std::vector<std::vector<Eigen::Vector3d>> asLines( const std::vector<CompiledPolygon> &polygons )
  {
    std::vector<std::vector<Eigen::Vector3d>> out;
    for ( const CompiledPolygon &p : polygons )
    {
      std::vector<Eigen::Vector3d> line;
      for ( const Eigen::Vector2d &v : p.pixels )
        line.emplace_back( v.x(), v.y(), 0.0 );
      out.push_back( line );
    }
    return out;
  }

  inline LineExtractionOptions aerialOptions()
  {
    LineExtractionOptions o;
    o.object.polarity = -1; // asphalt between bright kerbs and shoulders
    o.object.minContrast = 25.0;
    o.object.maxVariation = 14.0;
    o.object.minWidthPx = 6.0;
    o.object.maxWidthPx = 20.0;
    return o;
  }
  inline double meanRoadHeight( const AerialPair &pair )
  {
    double sum = 0;
    int n = 0;
    for ( const TruthRoadLine &l : pair.roads )
      for ( const Eigen::Vector3d &v : l.vertices )
      {
        sum += v.z();
        ++n;
      }
    return sum / n;
  }

} // namespace geostation::testing

#endif // GEOSTATION_TESTS_AERIALPAIRS_H
