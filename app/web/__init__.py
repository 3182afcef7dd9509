"""The web face of `soccer-lab serve`: the server, its JSON API, the viser UI, classroom mode and who may do what."""
