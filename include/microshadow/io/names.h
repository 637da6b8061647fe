// The spellings of an enum's values, kept in one table per enum: the name of a value, the value of a name,
// and one wording of the error for an unknown name (it lists the known ones, so the message cannot drift from
// the table).
#pragma once

#include <microshadow/io/error.h>

#include <span>
#include <string>

namespace msh {

template <class E>
struct Named {
  E value;
  const char* name;
};

// The name of `value` in `table`; "?" when the table lacks it.
template <class E>
const char* name_of(std::span<const Named<E>> table, E value) {
  for (const Named<E>& n : table)
    if (n.value == value) return n.name;
  return "?";
}

// "a, b, c": the names of `table`, in order.
template <class E>
std::string names_of(std::span<const Named<E>> table) {
  std::string s;
  for (const Named<E>& n : table) s += (s.empty() ? "" : ", ") + std::string(n.name);
  return s;
}

// The value named `name`; InputError "unknown <what> '<name>' (known: a, b, c)" when none is.
template <class E>
E value_of(std::span<const Named<E>> table, const std::string& name, const std::string& what) {
  for (const Named<E>& n : table)
    if (name == n.name) return n.value;
  throw InputError("unknown " + what + " '" + name + "' (known: " + names_of(table) + ")");
}

}  // namespace msh
