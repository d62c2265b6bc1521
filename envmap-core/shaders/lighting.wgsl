// envmap shaders: the image-based-lighting lookups (to be written).
