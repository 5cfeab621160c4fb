"""Who sees whom: the neighbour views of a tick and the floor (target) sensor."""
