"""HeartToHeart4 files (Kondo's Windows motion editor)."""
