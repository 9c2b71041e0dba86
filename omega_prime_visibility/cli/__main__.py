"""``python -m omega_prime_visibility.cli`` runs the command line, as ``python -m omega_prime_visibility`` does."""

from . import main

if __name__ == "__main__":
    main()
