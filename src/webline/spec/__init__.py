"""Line files: schema, loading, checking, dumping."""
