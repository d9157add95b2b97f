/***************************************************************************
  blockimport.cpp - what every block importer returns, and georeferencing
 ***************************************************************************/
#include "io/blockimport.h"

#include <cstdio>
#include <sstream>
#include <iomanip>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "io/textfile.h"

namespace geostation
{
  namespace
  {
    std::string fixed( double v, int decimals )
    {
      char buf[64];
      std::snprintf( buf, sizeof( buf ), "%.*f", decimals, v );
      return buf;
    }
  }

  void georeferenceImport( BlockImportSummary &import, const KnownPositions &known )
  {
    std::vector<Eigen::Vector3d> source, target;
    std::vector<std::string> names, unmatched;
    const bool fromCameras = !known.cameraCentres.empty();
    if ( fromCameras )
    {
      for ( const auto &[name, position] : known.cameraCentres )
      {
        auto byName = import.imageIdBySourceName.find( name );
        const std::string imageId = byName != import.imageIdBySourceName.end() ? byName->second : name;
        const BlockImage *image = import.block.findImage( imageId );
        if ( !image || !image->exterior )
        {
          unmatched.push_back( name );
          continue;
        }
        source.push_back( image->exterior->projectionCentre );
        target.push_back( position );
        names.push_back( name );
      }
    }
    else
    {
      std::map<std::string, const ImportedTiePoint *> byId;
      for ( const ImportedTiePoint &p : import.tiePoints )
        byId[p.pointId] = &p;
      for ( const auto &[name, position] : known.controlPoints )
      {
        auto it = byId.find( name );
        if ( it == byId.end() )
        {
          unmatched.push_back( name );
          continue;
        }
        source.push_back( it->second->world );
        target.push_back( position );
        names.push_back( name );
      }
    }
    const std::string what = fromCameras ? "camera centres" : "control points";
    if ( source.size() < 3 )
      throw std::invalid_argument( "the georeference needs at least three " + what + " that are in the model; " + std::to_string( source.size() ) + " of "
                                   + std::to_string( source.size() + unmatched.size() ) + " given match"
                                   + ( unmatched.empty() ? std::string() : " (not in the model: \"" + unmatched.front() + "\"" + ( unmatched.size() > 1 ? ", ..." : "" ) + ")" ) );

    SimilarityFitSummary fit = fitSimilarityTransform( source, target, names );
    const SimilarityTransform &t = fit.targetFromSource;
    for ( BlockImage &image : import.block.images )
      if ( image.exterior )
        image.exterior = t.apply( *image.exterior );
    for ( ImportedTiePoint &p : import.tiePoints )
      p.world = t.apply( p.world );
    for ( const std::string &name : unmatched )
      import.dropped.push_back( "the known position of \"" + name + "\" names nothing in the model and was not used" );
    import.converted.push_back( "georeferenced by a similarity transform fitted to " + std::to_string( source.size() ) + " " + what + ": scale " + fixed( t.scale, 6 )
                                + ", RMS residual " + fixed( fit.rmsM, 3 ) + " m, largest " + fixed( fit.maxM, 3 ) + " m" );
    if ( fit.spreadRatio < 0.05 )
      import.warnings.push_back( "the " + what + " of the georeference lie nearly on one line (spread " + fixed( fit.spreadRatio, 3 )
                                 + "), so the rotation about that line is weakly determined; add control points off the line" );
    import.georeference = std::move( fit );
    import.georeferenceFrom = what;
  }

  std::string importReportJsonText( const BlockImportSummary &import )
  {
    nlohmann::json report;
    report["format"] = import.format;
    report["crs"] = import.block.crs;
    report["cameras"] = import.block.cameras.size();
    report["images"] = import.block.images.size();
    report["stations"] = import.block.stations.size();
    report["tie_points"] = import.tiePoints.size();
    report["observations"] = import.observations.size();
    report["control_points"] = import.controlPoints.size();
    report["converted"] = import.converted;
    report["dropped"] = import.dropped;
    report["warnings"] = import.warnings;
    if ( import.georeference )
    {
      const SimilarityFitSummary &g = *import.georeference;
      const SimilarityTransform &t = g.targetFromSource;
      nlohmann::json geo;
      geo["from"] = import.georeferenceFrom;
      geo["scale"] = t.scale;
      geo["rotation"] = { { t.rotation( 0, 0 ), t.rotation( 0, 1 ), t.rotation( 0, 2 ) },
        { t.rotation( 1, 0 ), t.rotation( 1, 1 ), t.rotation( 1, 2 ) },
        { t.rotation( 2, 0 ), t.rotation( 2, 1 ), t.rotation( 2, 2 ) } };
      geo["translation"] = { t.translation.x(), t.translation.y(), t.translation.z() };
      geo["rms_m"] = g.rmsM;
      geo["max_m"] = g.maxM;
      geo["sigma0_m"] = g.sigma0M;
      geo["spread_ratio"] = g.spreadRatio;
      nlohmann::json residuals = nlohmann::json::array();
      for ( const SimilarityPairResidual &r : g.residuals )
        residuals.push_back( { { "name", r.name }, { "dx", r.residualM.x() }, { "dy", r.residualM.y() }, { "dz", r.residualM.z() }, { "d", r.residualM.norm() } } );
      geo["residuals"] = residuals;
      report["georeference"] = geo;
    }
    else
      report["georeference"] = nullptr;
    return report.dump( 2 ) + "\n";
  }

  void writeTiePointTables( const BlockImportSummary &import, const std::filesystem::path &observationsFile, const std::filesystem::path &pointsFile )
  {
    if ( !observationsFile.empty() )
    {
      std::ostringstream out;
      out << std::setprecision( 17 ) << "point_id,image_id,col,row\n";
      for ( const ImportedObservation &o : import.observations )
        out << csvField( o.pointId ) << ',' << csvField( o.imageId ) << ',' << o.pixelInImage.x() << ',' << o.pixelInImage.y() << '\n';
      writeTextFileAtomically( observationsFile, out.str() );
    }
    if ( !pointsFile.empty() )
    {
      std::ostringstream out;
      out << std::setprecision( 17 ) << "point_id,X,Y,Z,error_px\n";
      for ( const ImportedTiePoint &p : import.tiePoints )
        out << csvField( p.pointId ) << ',' << p.world.x() << ',' << p.world.y() << ',' << p.world.z() << ',' << p.errorPx << '\n';
      writeTextFileAtomically( pointsFile, out.str() );
    }
  }

  void writeControlTable( const BlockImportSummary &import, const std::filesystem::path &controlFile )
  {
    std::ostringstream out;
    out << std::setprecision( 17 ) << "point_id,X,Y,Z,sx,sy,sz,role\n";
    for ( const ImportedControlPoint &p : import.controlPoints )
    {
      out << csvField( p.pointId ) << ',' << p.world.x() << ',' << p.world.y() << ',' << p.world.z();
      for ( int k = 0; k < 3; ++k )
      {
        out << ',';
        if ( p.sigmaM )
          out << ( *p.sigmaM )[k];
      }
      out << ',' << ( p.check ? "check" : "control" ) << '\n';
    }
    writeTextFileAtomically( controlFile, out.str() );
  }

} // namespace geostation
