/***************************************************************************
  fuzzblockjson.cpp - the block file (*.geostation.json, docs/conventions.md §5)
  -------------------------------------------------------------------------
  Any text: Block::fromJsonText() either throws BlockFormatError with a
  message or gives a block whose JSON text reads back to the same text
  (what is loaded is what is saved: unknown keys, paths and numbers
  survive a round trip).
 ***************************************************************************/
#include "fuzztarget.h"

#include "io/block.h"

GEOSTATION_FUZZ_TARGET( block_json )
{
  using geostation::Block;
  const std::string text( reinterpret_cast<const char *>( data ), size );
  Block block;
  try
  {
    block = Block::fromJsonText( text, "/fuzz/input.geostation.json" );
  }
  catch ( const geostation::BlockFormatError &error )
  {
    geostation::fuzz::requireMessage( error );
    return 0;
  }
  const std::string saved = block.toJsonText();
  Block reread;
  try
  {
    reread = Block::fromJsonText( saved, "/fuzz/input.geostation.json" );
  }
  catch ( const geostation::BlockFormatError &error )
  {
    geostation::fuzz::violated( std::string( "a loaded block does not read back: " ) + error.what() + "\n" + saved );
  }
  if ( reread.toJsonText() != saved )
    geostation::fuzz::violated( "a block's JSON text changes on its second round trip:\n" + saved + "\n---\n" + reread.toJsonText() );
  geostation::fuzz::outcome( "read: " + std::to_string( block.cameras.size() ) + " cameras, " + std::to_string( block.images.size() ) + " images, round trip unchanged" );
  return 0;
}
