"""What each root is: its label, its frequency in both frames, and what motion it contains."""
