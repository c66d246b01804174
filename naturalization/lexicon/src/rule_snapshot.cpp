#include "flipper/naturalization/rule_snapshot.hpp"

#include <bit>
#include <cstring>

namespace flipper::naturalization {

namespace {

constexpr char kMagic[4] = {'F', 'L', 'X', 'S'};

template <int Bytes>
void put_le(std::string& out, std::uint64_t v) {
  char buf[Bytes];
  for (int i = 0; i < Bytes; ++i) {
    buf[i] = static_cast<char>((v >> (8 * i)) & 0xff);
  }
  out.append(buf, Bytes);  // one append: the per-byte push_back was most of a rebuild's encoding
}
void put_u32(std::string& out, std::uint32_t v) {
  put_le<4>(out, v);
}
void put_u64(std::string& out, std::uint64_t v) {
  put_le<8>(out, v);
}
void put_str(std::string& out, std::string_view s) {
  put_u32(out, static_cast<std::uint32_t>(s.size()));
  out.append(s);
}
void put_list(std::string& out, const std::vector<std::string>& v) {
  put_u32(out, static_cast<std::uint32_t>(v.size()));
  for (const auto& s : v) {
    put_str(out, s);
  }
}

/// A bounds-checked cursor: every read fails (and stays failed) past the end.
class Reader {
 public:
  explicit Reader(std::string_view in) : in_(in) {}
  bool ok() const { return ok_; }
  bool at_end() const { return pos_ == in_.size(); }
  std::uint64_t u(int bytes) {
    if (!need(static_cast<std::size_t>(bytes))) {
      return 0;
    }
    std::uint64_t v = 0;
    if constexpr (std::endian::native == std::endian::little) {
      std::memcpy(&v, in_.data() + pos_, static_cast<std::size_t>(bytes));  // the blob's order
    } else {
      for (int i = 0; i < bytes; ++i) {
        v |= static_cast<std::uint64_t>(static_cast<unsigned char>(in_[pos_ + i])) << (8 * i);
      }
    }
    pos_ += static_cast<std::size_t>(bytes);
    return v;
  }
  std::string_view str() {
    const auto n = static_cast<std::size_t>(u(4));
    if (!need(n)) {
      return {};
    }
    std::string_view s = in_.substr(pos_, n);
    pos_ += n;
    return s;
  }
  /// A list's count, refused when it could not fit in what is left (4 bytes per item at least).
  std::size_t count() {
    const auto n = static_cast<std::size_t>(u(4));
    if (n > (in_.size() - pos_) / 4) {
      ok_ = false;
    }
    return ok_ ? n : 0;
  }

 private:
  bool need(std::size_t n) {
    if (!ok_ || in_.size() - pos_ < n) {
      ok_ = false;
    }
    return ok_;
  }
  std::string_view in_;
  std::size_t pos_ = 0;
  bool ok_ = true;
};

/// Reads one rule; with `into` null only checks and skips it.
void read_one(Reader& r, StoredRuleView* into) {
  const auto created = static_cast<std::int64_t>(r.u(8));
  const auto definition = static_cast<std::int64_t>(r.u(8));
  std::string_view fields[7];  // id, lhs, semantics, author, head, how, decode_error
  for (auto& f : fields) {
    f = r.str();
  }
  std::vector<std::string_view>* lists[2] = {into ? &into->rhs : nullptr,
                                             into ? &into->body : nullptr};
  for (auto* list : lists) {
    const std::size_t n = r.count();
    if (list) {
      list->clear();
    }
    for (std::size_t i = 0; i < n && r.ok(); ++i) {
      const std::string_view s = r.str();
      if (list) {
        list->push_back(s);
      }
    }
  }
  if (!into) {
    return;
  }
  into->created = created;
  into->definition = definition;
  into->id = fields[0];
  into->lhs = fields[1];
  into->semantics = fields[2];
  into->author = fields[3];
  into->head = fields[4];
  into->how = fields[5];
  into->decode_error = fields[6];
}

}  // namespace

RuleSnapshotWriter::RuleSnapshotWriter() {
  out_.append(kMagic, sizeof kMagic);
  put_u32(out_, kRuleSnapshotFormat);
  put_u64(out_, 0);  // the count, filled in by finish()
}

void RuleSnapshotWriter::add(const StoredRule& r) {
  put_u64(out_, static_cast<std::uint64_t>(r.created));
  put_u64(out_, static_cast<std::uint64_t>(r.definition));
  for (const std::string* s :
       {&r.id, &r.lhs, &r.semantics, &r.author, &r.head, &r.how, &r.decode_error}) {
    put_str(out_, *s);
  }
  put_list(out_, r.rhs);
  put_list(out_, r.body);
  ++count_;
}

std::string RuleSnapshotWriter::finish() {
  for (int i = 0; i < 8; ++i) {
    out_[8 + static_cast<std::size_t>(i)] = static_cast<char>((count_ >> (8 * i)) & 0xff);
  }
  std::string done = std::move(out_);
  *this = RuleSnapshotWriter();
  return done;
}

StoredRule StoredRuleView::materialize() const {
  StoredRule r;
  r.id = id;
  r.lhs = lhs;
  r.rhs.assign(rhs.begin(), rhs.end());
  r.semantics = semantics;
  r.author = author;
  r.head = head;
  r.body.assign(body.begin(), body.end());
  r.how = how;
  r.created = created;
  r.definition = definition;
  r.decode_error = decode_error;
  return r;
}

bool read_rule_snapshot(std::string_view blob,
                        const std::function<void(const StoredRuleView&)>& each) {
  if (blob.size() < 16 || std::memcmp(blob.data(), kMagic, sizeof kMagic) != 0) {
    return false;
  }
  Reader head(blob.substr(4));
  if (head.u(4) != kRuleSnapshotFormat) {
    return false;
  }
  const std::uint64_t n = head.u(8);
  // Pass 1: the whole blob is well formed (a damaged one hands out nothing).
  Reader check(blob.substr(16));
  for (std::uint64_t i = 0; i < n && check.ok(); ++i) {
    read_one(check, nullptr);
  }
  if (!check.ok() || !check.at_end()) {
    return false;
  }
  // Pass 2: hand out views, one reused StoredRuleView.
  Reader r(blob.substr(16));
  StoredRuleView view;
  for (std::uint64_t i = 0; i < n; ++i) {
    read_one(r, &view);
    each(view);
  }
  return true;
}

std::uint64_t snapshot_checksum(std::string_view blob) {
  // Word-wise multiply-rotate (xxHash64's round): fast enough to check megabytes at start-up.
  constexpr std::uint64_t k1 = 0x9E3779B185EBCA87ULL, k2 = 0xC2B2AE3D27D4EB4FULL;
  std::uint64_t h = 0x27D4EB2F165667C5ULL ^ blob.size();
  auto round = [&](std::uint64_t w) {
    h ^= w * k2;
    h = (h << 31) | (h >> 33);
    h *= k1;
  };
  std::size_t i = 0;
  for (; i + 8 <= blob.size(); i += 8) {
    std::uint64_t w;
    std::memcpy(&w, blob.data() + i, 8);
    round(w);
  }
  std::uint64_t tail = 0;
  for (std::size_t j = 0; i + j < blob.size(); ++j) {
    tail |= static_cast<std::uint64_t>(static_cast<unsigned char>(blob[i + j])) << (8 * j);
  }
  round(tail);
  h ^= h >> 33;
  h *= k2;
  h ^= h >> 29;
  return h;
}

}  // namespace flipper::naturalization
