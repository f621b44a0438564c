//! Chunk storage, the world map, neighbourhood gathers and the chunk codec.
