"""conde_worlds: worlds and the procedurally generated competition track of conde_sim."""
