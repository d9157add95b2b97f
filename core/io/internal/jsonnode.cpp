/***************************************************************************
  jsonnode.cpp - reading JSON with the path of every value, for messages
 ***************************************************************************/
#include "io/internal/jsonnode.h"

#include <cmath>

namespace geostation
{

  using json = nlohmann::json;

  std::string describeJsonType( const json &value )
  {
    switch ( value.type() )
    {
      case json::value_t::null:
        return "null";
      case json::value_t::boolean:
        return "a boolean";
      case json::value_t::string:
        return "the string \"" + value.get<std::string>() + "\"";
      case json::value_t::number_integer:
      case json::value_t::number_unsigned:
      case json::value_t::number_float:
        return "the number " + value.dump();
      case json::value_t::object:
        return "an object";
      case json::value_t::array:
        return "an array";
      default:
        return "an unreadable value";
    }
  }

  void JsonNode::requireObject() const
  {
    if ( !mValue.is_object() )
      fail( "expected an object, found " + describeJsonType( mValue ) );
  }

  JsonNode JsonNode::child( const char *key ) const
  {
    if ( !mValue.contains( key ) )
      fail( std::string( "the required key \"" ) + key + "\" is missing" );
    return JsonNode( mValue.at( key ), mPath + "." + key, mFile );
  }

  std::vector<JsonNode> JsonNode::arrayItems( bool allowEmpty, const std::string &what ) const
  {
    if ( !mValue.is_array() )
      fail( "expected an array of " + what + ", found " + describeJsonType( mValue ) );
    if ( !allowEmpty && mValue.empty() )
      fail( "expected at least one of " + what + ", found an empty array" );
    std::vector<JsonNode> items;
    for ( size_t i = 0; i < mValue.size(); ++i )
      items.emplace_back( mValue[i], mPath + "[" + std::to_string( i ) + "]", mFile );
    return items;
  }

  std::string JsonNode::string( bool allowEmpty ) const
  {
    if ( !mValue.is_string() )
      fail( "expected a string, found " + describeJsonType( mValue ) );
    const std::string s = mValue.get<std::string>();
    if ( !allowEmpty && s.empty() )
      fail( "expected a non-empty string" );
    return s;
  }

  double JsonNode::number( const std::string &meaning ) const
  {
    if ( !mValue.is_number() )
      fail( "expected a number (" + meaning + "), found " + describeJsonType( mValue ) );
    const double v = mValue.get<double>();
    if ( !std::isfinite( v ) )
      fail( "expected a finite number (" + meaning + ")" );
    return v;
  }

  double JsonNode::positiveNumber( const std::string &meaning, bool allowZero ) const
  {
    const std::string kind = allowZero ? "non-negative" : "positive";
    if ( !mValue.is_number() )
      fail( "expected a " + kind + " number (" + meaning + "), found " + describeJsonType( mValue ) );
    const double v = number( meaning );
    if ( allowZero ? v < 0.0 : v <= 0.0 )
      fail( "expected a " + kind + " number (" + meaning + "), found " + mValue.dump() );
    return v;
  }

  int JsonNode::positiveInteger( const std::string &meaning ) const
  {
    if ( !mValue.is_number_integer() || mValue.get<long long>() <= 0 || mValue.get<long long>() > 10000000 )
      fail( "expected a positive whole number (" + meaning + "), found " + describeJsonType( mValue ) );
    return mValue.get<int>();
  }

} // namespace geostation
