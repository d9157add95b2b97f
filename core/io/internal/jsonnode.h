/***************************************************************************
  jsonnode.h - reading JSON with the path of every value, for messages
  -------------------------------------------------------------------------
  A value and its JSON path ("$.images[2].omega"): typed accessors that
  throw BlockFormatError naming the file, the path and what was expected.
 ***************************************************************************/
#ifndef GEOSTATION_IO_JSONNODE_H
#define GEOSTATION_IO_JSONNODE_H

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/block.h"

namespace geostation
{

  //! "a boolean", "the string \"x\"", "the number 3", ... for messages.
  std::string describeJsonType( const nlohmann::json &value );

  class JsonNode
  {
    public:
      JsonNode( const nlohmann::json &value, std::string path, const std::string &file )
        : mValue( value ), mPath( std::move( path ) ), mFile( file ) {}

      [[noreturn]] void fail( const std::string &problem ) const { throw BlockFormatError( mFile, mPath, problem ); }

      const nlohmann::json &value() const { return mValue; }
      const std::string &path() const { return mPath; }
      bool has( const char *key ) const { return mValue.contains( key ); }

      void requireObject() const;
      //! The member `key`; fails if it is missing.
      JsonNode child( const char *key ) const;
      std::vector<JsonNode> arrayItems( bool allowEmpty, const std::string &what ) const;
      std::string string( bool allowEmpty = false ) const;
      double number( const std::string &meaning ) const;
      double positiveNumber( const std::string &meaning, bool allowZero = false ) const;
      int positiveInteger( const std::string &meaning ) const;

    private:
      const nlohmann::json &mValue;
      std::string mPath;
      const std::string &mFile;
  };

} // namespace geostation

#endif // GEOSTATION_IO_JSONNODE_H
