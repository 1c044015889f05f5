"""HeartToHeart4 projects on the board: ROM images, simulation in the emulator, upload."""
