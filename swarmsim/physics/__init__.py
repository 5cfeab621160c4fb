"""The pymunk Space: bodies, walls, contacts, parked (sleeping) bodies, and the direct calls into
Chipmunk."""
