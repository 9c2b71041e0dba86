"""``python -m omega_prime_visibility`` runs the command line (``run``, ``batch``, ``engines``)."""

from .cli import main

if __name__ == "__main__":
    main()
