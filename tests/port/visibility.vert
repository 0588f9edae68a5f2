// The visibility pass's vertices (§Rasterizer step 1): the oracle's clip position, handed to GL's
// own clipper and rasterizer. Vertex pulling: gl_VertexID is the index from the mesh's element buffer.
void main() { gl_Position = SnapToGrid(Transform(viewProjection, MeshPosition(uint(gl_VertexID)))); }
