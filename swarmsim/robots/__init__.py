"""What a robot does imperfectly: sensing and motion noise (later: drive models)."""
