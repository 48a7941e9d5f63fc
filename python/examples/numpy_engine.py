"""A plain NumPy engine of the pipe lattice gas, written from MODEL.md Part A
for the project's default reading (ph94+gravity-first+wall-move+inject-late),
for `granular_automata.validate` to check against the reference engine.

It draws its own random numbers (NumPy's PCG64), so its runs differ from the
reference's run by run; `validate` compares distributions, not draws.

`WrongPipe` is the same engine with one deliberate error (a head-on pair
always rotates the same way, R1 of MODEL.md A3), which level 1 must catch.
"""

import numpy as np

# channel c as a bit of the site byte (MODEL.md A1); 0 is the rest particle
REST = 1


def bit(c):
    return 1 << c


def turn(c, k):
    """Channel c turned by k bonds counter-clockwise (channels 1..6)."""
    return (c - 1 + k) % 6 + 1


def collision_table(p):
    """For each of the 128 states: a list of (probability, new state, extra
    rest particles), from R1-R5 of MODEL.md A3 ("exactly": nothing else on
    the site)."""
    table = {}
    for c in range(1, 7):
        a, b = bit(c), bit(turn(c, 3))
        # R1: a head-on pair rotates by +60 or -60 degrees, 1/2 each
        table[a | b] = [(0.5, bit(turn(c, 1)) | bit(turn(c, 4)), 0),
                        (0.5, bit(turn(c, 2)) | bit(turn(c, 5)), 0)]
        # R4: rest particle and a head-on pair: three rest particles, two extra
        table[REST | a | b] = [(1.0, REST, 2)]
        # R2: {c, c+2} -> {0, c+1} with probability p
        s = bit(c) | bit(turn(c, 2))
        table[s] = [(p, REST | bit(turn(c, 1)), 0), (1.0 - p, s, 0)]
        # R5: {0, c, c+2} -> {0, c+1} and one extra rest particle
        table[REST | s] = [(1.0, REST | bit(turn(c, 1)), 1)]
    for c in (1, 2):
        s = bit(c) | bit(turn(c, 2)) | bit(turn(c, 4))
        # R3: {c, c+2, c+4} -> {0, c', c'+3} for c' = c, c+1, c+2, p/3 each
        table[s] = [(p / 3, REST | bit(turn(c, k)) | bit(turn(c, k + 3)), 0) for k in range(3)]
        table[s].append((1.0 - p, s, 0))
    return table


# the neighbour of (x, y) along channel c (MODEL.md A1: odd columns, o = 1,
# sit half a row higher)
_NEIGHBOURS = {
    1: lambda x, y, o: (x, y + 1),
    2: lambda x, y, o: (x - 1, y + o),
    3: lambda x, y, o: (x - 1, y - 1 + o),
    4: lambda x, y, o: (x, y - 1),
    5: lambda x, y, o: (x + 1, y - 1 + o),
    6: lambda x, y, o: (x + 1, y + o),
}

# the walls (MODEL.md A6): channels heading in, bounce-back, mirrored
LEFT = {"into": (2, 3), "bounce": (5, 6), "specular": (6, 5)}
RIGHT = {"into": (6, 5), "bounce": (3, 2), "specular": (2, 3)}


class NumpyPipe:
    """One run of the pipe, the default reading, from MODEL.md A2-A8."""

    def __init__(self, params, rules="default", seed=1):
        if rules not in ("default", "ph94+gravity-first+wall-move+inject-late"):
            raise ValueError(f"this engine implements the default reading only, not {rules!r}")
        self.w, self.l = params["width"], params["length"]
        self.p, self.g, self.b = params["p"], params["g"], params["b"]
        self.bin = params["bin"]
        self.open = params["boundary"] == "open"
        self.inject_rate = params.get("inject") or 0.0
        self.rng = np.random.default_rng(seed)
        self.table = collision_table(self.p)
        self.injected = self.out_bottom = self.out_top = 0
        self.cells = np.zeros((self.w, self.l), dtype=np.uint8)
        if not self.open:
            # A8: each moving channel occupied with probability rho / 6
            occupied = self.rng.random((self.w, self.l, 6)) < params["rho"] / 6
            for c in range(1, 7):
                self.cells |= (occupied[:, :, c - 1] * bit(c)).astype(np.uint8)

    # --- what validate reads --------------------------------------------
    def state(self):
        return self.cells.copy()

    def set_state(self, state):
        self.cells = np.array(state, dtype=np.uint8).reshape(self.w, self.l)

    def bin_counts(self):
        counts = np.unpackbits(self.cells[:, :, None], axis=2).sum(axis=(0, 2))
        return counts.reshape(-1, self.bin).sum(axis=1).astype(np.float64)

    def channel_counts(self):
        return np.array([((self.cells >> c) & 1).sum() for c in range(7)], dtype=np.uint64)

    def flux(self):
        return (self.injected, self.out_bottom, self.out_top)

    # --- one step (MODEL.md A2) -------------------------------------------
    def step(self):
        self.gravity()
        self.collide()
        if self.open:
            self.inject()
        self.wall_move()
        self.propagate()

    def chance(self, q):
        return self.rng.random() < q

    def gravity(self):
        """A5, the ph94 wording: a rest particle falls (0 -> 4); at a site
        holding a rest particle a diagonal up-mover turns down (2 -> 3,
        6 -> 5); each move with probability g into an empty channel."""
        for x, y in zip(*np.nonzero(self.cells & REST)):
            s = int(self.cells[x, y])
            new = s
            for a, b in [(0, 4), (2, 3), (6, 5)]:
                if s & bit(a) and not s & bit(b) and self.chance(self.g):
                    new = (new & ~bit(a)) | bit(b)
            self.cells[x, y] = new

    def collide(self):
        """A3 by the table, then A4: extra rest particles walk, row by row
        from the bottom, left to right."""
        extras = []
        for x, y in zip(*np.nonzero(self.cells)):
            outcomes = self.table.get(int(self.cells[x, y]))
            if outcomes is None:
                continue
            u, acc = self.rng.random(), 0.0
            for prob, new, extra in outcomes:
                acc += prob
                if u < acc or prob == 1.0:
                    break
            self.cells[x, y] = new
            extras += [(int(x), int(y))] * extra
        for x, y in sorted(extras, key=lambda e: (e[1], e[0])):
            self.walk(x, y)

    def walk(self, x, y):
        """A4: hop to a neighbour chosen at random among the sites inside the
        pipe until the rest channel is empty."""
        for _ in range(1000 * self.w * self.l + 1_000_000):
            options = []
            for c in range(1, 7):
                nx, ny = _NEIGHBOURS[c](x, y, x % 2)
                if not 0 <= nx < self.w:
                    continue
                if self.open and not 0 <= ny < self.l:
                    continue
                options.append((nx, ny % self.l))
            x, y = options[self.rng.integers(len(options))]
            if not self.cells[x, y] & REST:
                self.cells[x, y] |= REST
                return
        raise RuntimeError("an extra rest particle found no empty rest channel")

    def inject(self):
        """A7 (inject-late): each empty inward channel 3, 4, 5 of the top row
        filled with probability I."""
        y = self.l - 1
        if self.inject_rate == 0.0:
            return
        for x in range(self.w):
            for c in (3, 4, 5):
                if not self.cells[x, y] & bit(c) and self.chance(self.inject_rate):
                    self.cells[x, y] |= bit(c)
                    self.injected += 1

    def walls(self):
        if self.w == 1:
            return [(0, LEFT), (0, RIGHT)]
        return [(0, LEFT), (self.w - 1, RIGHT)]

    def reflect(self, s, wall):
        """A6: the reflected channels of the particles of s heading into the
        wall: a lone one bounces back with probability b, else is mirrored;
        a pair bounces back."""
        a, b = (bool(s & bit(c)) for c in wall["into"])
        if a and b:
            return bit(wall["bounce"][0]) | bit(wall["bounce"][1])
        if not (a or b):
            return 0
        k = 0 if a else 1
        return bit(wall["bounce"][k] if self.chance(self.b) else wall["specular"][k])

    def wall_move(self):
        """A6 wall-move: reflect before propagation where the reflected
        channel is empty, so the particle moves this step."""
        if self.w == 1:
            return
        for x, wall in self.walls():
            heading = bit(wall["into"][0]) | bit(wall["into"][1])
            for y in np.nonzero(self.cells[x] & heading)[0]:
                s = int(self.cells[x, y])
                out = self.reflect(s, wall)
                if out and not s & out:
                    self.cells[x, y] = (s & ~heading) | out

    def propagate(self):
        """Every mover to its neighbour (A1); rows wrap or leave (A7); a
        particle heading into a wall is reflected in place (A6)."""
        new = self.cells & REST
        for x, y in zip(*np.nonzero(self.cells & 0x7E)):
            x, y = int(x), int(y)
            s = int(self.cells[x, y])
            for c in range(1, 7):
                if not s & bit(c):
                    continue
                nx, ny = _NEIGHBOURS[c](x, y, x % 2)
                if not 0 <= nx < self.w:
                    continue
                if not 0 <= ny < self.l:
                    if self.open:
                        if ny < 0:
                            self.out_bottom += 1
                        else:
                            self.out_top += 1
                        continue
                    ny %= self.l
                new[nx, ny] |= bit(c)
        for x, wall in self.walls():
            heading = bit(wall["into"][0]) | bit(wall["into"][1])
            for y in np.nonzero(self.cells[x] & heading)[0]:
                new[x, y] |= self.reflect(int(self.cells[x, y]), wall)
        self.cells = new


class WrongPipe(NumpyPipe):
    """The same engine with R1 always rotating by +60 degrees: a head-on pair
    never leaves as {c+2, c+5}."""

    def __init__(self, params, rules="default", seed=1):
        super().__init__(params, rules, seed)
        for state, outcomes in list(self.table.items()):
            if len(outcomes) == 2 and outcomes[0][0] == 0.5:
                self.table[state] = [(1.0, outcomes[0][1], 0)]
