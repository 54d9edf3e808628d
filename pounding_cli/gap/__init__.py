"""How far apart must two buildings be: relative placement, the geometry at rest, and the
separation each candidate pair needs over a record (``pound gap``)."""
