// A write transaction on a Catalogue: BEGIN IMMEDIATE on construction (waits up to
// Catalogue::kBusyTimeoutMs for another writer), COMMIT on commit(), ROLLBACK when destroyed
// without commit() (an exception unwinding past it leaves the catalogue as it was).
// Transactions do not nest. Use it to group a wave's writes: one fsync instead of thousands.
#pragma once

namespace hapstate {

class Catalogue;

class Transaction {
 public:
  explicit Transaction(Catalogue& catalogue);
  ~Transaction();
  Transaction(const Transaction&) = delete;
  Transaction& operator=(const Transaction&) = delete;

  // Commits; throws InputError if SQLite refuses (the transaction is then rolled back).
  // Calling it twice is a std::logic_error.
  void commit();

 private:
  Catalogue* catalogue_;
  bool done_ = false;
};

}  // namespace hapstate
