// The core language by example (docs/core-language.md §3, §10), for the help panel. Every example
// must parse (tests/apps/studio/browser/defects.test.mjs runs them all).
export const EXAMPLES = [
  ['move left', 'one step; a wall stops it and leaves a warning'],
  ['move up; move up', 'statements run in order, separated by ;'],
  ['visit room1', 'walk to the nearest cell of room1'],
  ['visit [3, 8]', 'walk to the cell x = 3, y = 8 (y grows upwards)'],
  ['visit world containing item is red', 'walk to the nearest cell with a red item'],
  ['pick item is red', 'pick one red item from the robot\'s cell'],
  ['pick every item', 'pick every item on the robot\'s cell'],
  ['drop item has shape circle', 'drop a held circle (has color/shape = is)'],
  ['visit room3 while avoiding room2', 'a path that never enters room2'],
  ['repeat 3 times move right', 'a loop with a count'],
  ['repeat 2 times { move up; move left }', 'braces group several statements'],
  ['foreach point in room1 containing item { visit point; pick every item }', 'every cell of an area'],
  ['foreach area in [room1, room2] { visit area; drop item }', 'every area of a collection'],
  ['if robot has item is blue drop item is blue', 'a condition (there is no else)'],
  ['while possible { move down } { move down }', 'move down while a step down is possible (at most 20 times)'],
  ['strict { move up; move up }', 'all or nothing: a failure rolls the block back'],
  ['visit area with corners [0, 0] and [3, 1]', 'a rectangle given by two corners'],
];
